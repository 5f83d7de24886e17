#include "core/distortion_fold.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace slamcmp {

namespace {

constexpr double kCornerMargin = 1.1;  // features are searched up to the border, and a little past it
constexpr int kRadialSteps = 1024;     // samples of the radius from the centre to the corner
// A lens squeezing the corner in from beyond 20 times its distorted radius is no lens: the walk stops.
constexpr int kMaxReach = 20;
constexpr int kGridRadii = 64, kGridAngles = 64;  // the Jacobian check's polar grid

// The distorted normalised radius of the image's farthest corner from the principal point.
double farthestCornerRadius(const CameraModel& c) {
  double r = 0;
  for (const double u : {-0.5, c.width - 0.5})
    for (const double v : {-0.5, c.height - 0.5}) r = std::max(r, c.normalisedFromPixel(Vec2(u, v)).norm());
  return r;
}

}  // namespace

std::string distortionFold(const CameraModel& camera) {
  if (!camera.hasDistortion()) return {};
  const double r_corner = farthestCornerRadius(camera), r_needed = kCornerMargin * r_corner;
  // The radial part alone: on the x axis without tangential terms, distort() gives r * radial(r)
  // and J = diag(d(r * radial(r))/dr, radial(r)).
  CameraModel radial_only = camera;
  radial_only.distortion[2] = radial_only.distortion[3] = 0.0;
  const double step = r_needed / kRadialSteps;
  double r_reach = 0;  // the undistorted radius that maps to r_needed
  for (int i = 1; i <= kMaxReach * kRadialSteps && r_reach == 0; ++i) {
    const double r = i * step;
    Mat2 J;
    const double r_distorted = radial_only.distort(Vec2(r, 0), &J).x();
    if (!(J.allFinite() && J(1, 1) > 0 && J(0, 0) > 0)) {
      std::ostringstream s;
      s << "the lens model folds inside the image: r * radial(r) stops growing at normalised radius "
        << r_distorted << " (undistorted " << r << ") but must grow to " << r_needed << " (" << kCornerMargin
        << "x the farthest corner's " << r_corner << ")";
      return s.str();
    }
    if (r_distorted >= r_needed) r_reach = r;
  }
  if (r_reach == 0) {
    std::ostringstream s;
    s << "the lens model squeezes more than " << kMaxReach << " times the image's corner radius into it";
    return s.str();
  }
  // With the radial part increasing, only the tangential terms can make the Jacobian singular.
  const double two_pi = 2 * std::acos(-1.0);
  for (int i = 1; i <= kGridRadii; ++i)
    for (int j = 0; j < kGridAngles; ++j) {
      const double r = r_reach * i / kGridRadii, angle = two_pi * j / kGridAngles;
      Mat2 J;
      const Vec2 xy_distorted = camera.distort(Vec2(r * std::cos(angle), r * std::sin(angle)), &J);
      if (!(J.determinant() > 0)) {
        const Vec2 uv = camera.pixelFromNormalised(xy_distorted);
        std::ostringstream s;
        s.precision(4);
        s << "the lens model folds near pixel (" << uv.x() << ", " << uv.y()
          << "): its tangential terms make the projection's Jacobian singular there";
        return s.str();
      }
    }
  return {};
}

}  // namespace slamcmp
