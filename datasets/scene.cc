#include "datasets/scene.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slamcmp {

namespace {

// Integral of the unit square wave (+1 on [0, 1), -1 on [1, 2), period 2): a triangle wave.
double squareWaveIntegral(double x) {
  const double m = x - 2.0 * std::floor(0.5 * x);  // in [0, 2)
  return 1.0 - std::abs(m - 1.0);
}

// Box-filtered square wave and pattern indicator along one board axis, in square units: the
// squares cover [lo, hi], the filter is [x - w/2, x + w/2]. Returns the mean of the square wave
// over the part inside [lo, hi] (divided by w) and the fraction inside.
void filteredSquares(double x, double w, double lo, double hi, double* wave, double* inside) {
  const double a = std::max(x - 0.5 * w, lo), b = std::min(x + 0.5 * w, hi);
  if (b <= a) {
    *wave = *inside = 0.0;
    return;
  }
  *wave = (squareWaveIntegral(b) - squareWaveIntegral(a)) / w;
  *inside = (b - a) / w;
}

}  // namespace

TexturedRect Scene::boardRect() const {
  TexturedRect r;
  r.name = "board";
  const double s = target.square_size;
  r.origin = Vec3(-s - board_margin, -s - board_margin, 0.0);
  r.axis_u = Vec3::UnitX();
  r.axis_v = Vec3::UnitY();
  r.size_u = (target.cols + 1) * s + 2 * board_margin;
  r.size_v = (target.rows + 1) * s + 2 * board_margin;
  r.normal = -Vec3::UnitZ();
  r.shade = surfaces[boardWall()].shade;
  return r;
}

double sampleAlbedo(const TexturedRect& rect, const Vec3& p_world) {
  const Vec3 d = p_world - rect.origin;
  const double fu = std::clamp(d.dot(rect.axis_u) / rect.texel - 0.5, 0.0, rect.albedo.cols - 1.001);
  const double fv = std::clamp(d.dot(rect.axis_v) / rect.texel - 0.5, 0.0, rect.albedo.rows - 1.001);
  const int iu = static_cast<int>(fu), iv = static_cast<int>(fv);
  const double au = fu - iu, av = fv - iv;
  const uchar* row0 = rect.albedo.ptr<uchar>(iv) + iu;
  const uchar* row1 = rect.albedo.ptr<uchar>(iv + 1) + iu;
  return (1 - av) * ((1 - au) * row0[0] + au * row0[1]) + av * ((1 - au) * row1[0] + au * row1[1]);
}

SceneView::SceneView(const Scene& scene, const SE3& T_world_camera, double footprint)
    : scene_(scene), T_world_camera_(T_world_camera), footprint_(footprint) {
  const TexturedRect board = scene.boardRect();
  board_lo_ = board.origin.head<2>();
  board_hi_ = board_lo_ + Vec2(board.size_u, board.size_v);
  const SE3 T_camera_world = T_world_camera.inverse();
  for (const SceneBox& box : scene.boxes) {
    BoxInView v;
    v.box = &box;
    v.R_box_camera = box.R_world_box.transpose() * T_world_camera.R();
    v.p_camera_in_box = box.R_world_box.transpose() * (T_world_camera.t() - box.centre);
    // A pinhole image of a convex body lies inside the bounds of its corners' images when all
    // corners are in front of the camera.
    v.cull = true;
    v.xy_lo = Vec2::Constant(std::numeric_limits<double>::infinity());
    v.xy_hi = -v.xy_lo;
    for (int k = 0; k < 8; ++k) {
      const Vec3 corner_box((k & 1 ? 1 : -1) * box.half_size.x(), (k & 2 ? 1 : -1) * box.half_size.y(),
                            (k & 4 ? 1 : -1) * box.half_size.z());
      const Vec3 p_camera = T_camera_world * (box.centre + box.R_world_box * corner_box);
      if (p_camera.z() < 1e-6) {
        v.cull = false;
        break;
      }
      const Vec2 xy(p_camera.x() / p_camera.z(), p_camera.y() / p_camera.z());
      v.xy_lo = v.xy_lo.cwiseMin(xy);
      v.xy_hi = v.xy_hi.cwiseMax(xy);
    }
    boxes_.push_back(v);
  }
}

SceneHit SceneView::intersect(double x, double y) const {
  const Vec3 ray_camera(x, y, 1.0);
  const Vec3 d = T_world_camera_.R() * ray_camera;
  const Vec3& c = T_world_camera_.t();
  SceneHit hit;
  // The camera is inside the room: the ray leaves it through the nearest of three walls.
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 3; ++k) {
    if (d[k] == 0.0) continue;
    const bool to_max = d[k] > 0;
    const double t = ((to_max ? scene_.room_max[k] : scene_.room_min[k]) - c[k]) / d[k];
    if (t < best) {
      best = t;
      hit.surface = scene_.room_face[2 * k + (to_max ? 1 : 0)];
    }
  }
  for (const BoxInView& v : boxes_) {
    if (v.cull && (x < v.xy_lo.x() || x > v.xy_hi.x() || y < v.xy_lo.y() || y > v.xy_hi.y())) continue;
    // Slab test in the box frame.
    const Vec3 d_box = v.R_box_camera * ray_camera;
    const Vec3& o = v.p_camera_in_box;
    const Vec3& h = v.box->half_size;
    double t_near = 0.0, t_far = best;
    int face = -1;
    bool miss = false;
    for (int k = 0; k < 3 && !miss; ++k) {
      if (d_box[k] == 0.0) {
        miss = std::abs(o[k]) > h[k];
        continue;
      }
      const double inv = 1.0 / d_box[k];
      double t0 = (-h[k] - o[k]) * inv, t1 = (h[k] - o[k]) * inv;
      if (t0 > t1) std::swap(t0, t1);
      if (t0 > t_near) {
        t_near = t0;
        face = 2 * k + (d_box[k] > 0 ? 0 : 1);  // entering through the face towards the camera
      }
      t_far = std::min(t_far, t1);
      miss = t_near > t_far;
    }
    if (miss || face < 0 || v.box->face[face] < 0) continue;
    best = t_near;
    hit.surface = v.box->face[face];
  }
  hit.depth = best;
  hit.p_world = c + best * d;
  return hit;
}

double SceneView::boardAlbedo(const Vec3& p_world, double width_x, double width_y) const {
  const ChessboardTarget& t = scene_.target;
  const double s = t.square_size;
  // Square (a, b), a in 0..cols, b in 0..rows, covers [a-1, a] x [b-1, b] in square units and is
  // black when a + b is even: the square diagonally outside corner (0, 0) is black (SPEC section 2).
  // Black = (1 + wave_x wave_y) / 2 inside the pattern; the box filter of this separable product
  // is the product of the filtered factors.
  double wave_x, in_x, wave_y, in_y;
  filteredSquares(p_world.x() / s, std::max(width_x / s, 1e-9), -1.0, t.cols, &wave_x, &in_x);
  filteredSquares(p_world.y() / s, std::max(width_y / s, 1e-9), -1.0, t.rows, &wave_y, &in_y);
  const double black = 0.5 * (in_x * in_y + wave_x * wave_y);
  return scene_.board_white - (scene_.board_white - scene_.board_black) * black;
}

double SceneView::radiance(double x, double y) const {
  const SceneHit hit = intersect(x, y);
  const TexturedRect& rect = scene_.surfaces[hit.surface];
  if (hit.surface == scene_.boardWall()) {
    const Vec3& p = hit.p_world;
    if (p.x() >= board_lo_.x() && p.y() >= board_lo_.y() && p.x() <= board_hi_.x() &&
        p.y() <= board_hi_.y()) {
      // The sample's footprint on the board (z = 0): how far the hit point moves when the ray
      // (x, y, 1) moves by `footprint` along x and along y; the box filter covers its bounds.
      const Mat3& R = T_world_camera_.R();
      const Vec3 d = R * Vec3(x, y, 1.0);
      const Vec3 dp_dx = hit.depth * (R.col(0) - (R(2, 0) / d.z()) * d);
      const Vec3 dp_dy = hit.depth * (R.col(1) - (R(2, 1) / d.z()) * d);
      const double width_x = footprint_ * (std::abs(dp_dx.x()) + std::abs(dp_dy.x()));
      const double width_y = footprint_ * (std::abs(dp_dx.y()) + std::abs(dp_dy.y()));
      return rect.shade * boardAlbedo(hit.p_world, width_x, width_y);
    }
  }
  return rect.shade * sampleAlbedo(rect, hit.p_world);
}

}  // namespace slamcmp
