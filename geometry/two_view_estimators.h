#pragma once
// The minimal solvers of two views as RANSAC estimators (geometry/ransac.h), on undistorted
// normalised coordinates with residuals in pixels^2 (focal2 = focal_px^2): the 8-point essential
// matrix under the Sampson distance, the 4-point homography under the transfer error. Their
// solvers fit more than the minimal sample by least squares (refitOnInliers).
#include <cmath>
#include <limits>
#include <vector>

#include "core/geometry.h"
#include "geometry/essential_eight_point.h"
#include "geometry/homography_pose.h"

namespace slamcmp {

// The points of `sample`, in its order.
inline std::vector<Vec2> selected(const std::vector<Vec2>& points, const std::vector<int>& sample) {
  std::vector<Vec2> out;
  out.reserve(sample.size());
  for (int i : sample) out.push_back(points[i]);
  return out;
}

// x_b^T E x_a = 0 (essential_eight_point.h's convention).
struct EssentialEstimator {
  using Model = Mat3;
  static constexpr int kMinSamples = 8;
  const std::vector<Vec2>& xy_a;
  const std::vector<Vec2>& xy_b;
  double focal2;  // focal_px^2: Sampson distances in pixels^2

  int numData() const { return static_cast<int>(xy_a.size()); }
  std::vector<Model> estimate(const std::vector<int>& sample) const {
    return {essentialEightPoint(selected(xy_a, sample), selected(xy_b, sample))};
  }
  double squaredError(const Model& E, int i) const { return focal2 * sampsonErrorSquared(E, xy_a[i], xy_b[i]); }
};

// x_b ~ H x_a by the 4-point DLT; residual: the transfer error |x_b - H x_a|, pixels^2.
struct HomographyEstimator {
  using Model = Mat3;
  static constexpr int kMinSamples = 4;
  const std::vector<Vec2>& xy_a;
  const std::vector<Vec2>& xy_b;
  double focal2;

  int numData() const { return static_cast<int>(xy_a.size()); }
  std::vector<Model> estimate(const std::vector<int>& sample) const {
    return {homographyDlt(selected(xy_a, sample), selected(xy_b, sample))};
  }
  double squaredError(const Model& H, int i) const {
    const double e2 = focal2 * ((H * xy_a[i].homogeneous()).hnormalized() - xy_b[i]).squaredNorm();
    return std::isfinite(e2) ? e2 : std::numeric_limits<double>::infinity();
  }
};

}  // namespace slamcmp
