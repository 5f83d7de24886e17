#include "eval/metrics/scene_distance.h"

#include <algorithm>
#include <cmath>

namespace slamcmp {

namespace {

// Distance from p to the segment a + t d, t in [0, 1].
double distanceToSegment(const Vec3& p, const Vec3& a, const Vec3& d) {
  const double dd = d.squaredNorm();
  const double t = dd > 0 ? std::clamp((p - a).dot(d) / dd, 0.0, 1.0) : 0.0;
  return (p - (a + t * d)).norm();
}

}  // namespace

double distanceToSurface(const Vec3& p_world, const SceneSurface& s) {
  const Vec3& u = s.edge_u;
  const Vec3& v = s.edge_v;
  const Vec3 q = p_world - s.origin;
  const Vec3 n = u.cross(v);
  const double nn = n.squaredNorm();  // = |u|^2 |v|^2 - (u.v)^2, the Gram determinant
  if (nn > 0) {
    // (a, b) of the point's orthogonal projection onto the plane: q = a u + b v + c n.
    const double uu = u.dot(u), uv = u.dot(v), vv = v.dot(v), qu = q.dot(u), qv = q.dot(v);
    const double a = (qu * vv - qv * uv) / nn, b = (qv * uu - qu * uv) / nn;
    if (a >= 0 && a <= 1 && b >= 0 && b <= 1) return std::abs(q.dot(n)) / std::sqrt(nn);
  }
  // Projection outside (or a degenerate surface): the nearest point is on the boundary.
  return std::min({distanceToSegment(p_world, s.origin, u), distanceToSegment(p_world, s.origin, v),
                   distanceToSegment(p_world, s.origin + u, v), distanceToSegment(p_world, s.origin + v, u)});
}

std::vector<SceneSurface> sceneSurfaces(const SceneGeometry& scene) {
  std::vector<SceneSurface> all{scene.board};
  all.insert(all.end(), scene.surfaces.begin(), scene.surfaces.end());
  return all;
}

NearestSurface nearestSurface(const Vec3& p_world, const std::vector<SceneSurface>& surfaces) {
  NearestSurface best;
  for (size_t i = 0; i < surfaces.size(); ++i) {
    const double d = distanceToSurface(p_world, surfaces[i]);
    if (d < best.distance) best = {static_cast<int>(i), d};
  }
  return best;
}

}  // namespace slamcmp
