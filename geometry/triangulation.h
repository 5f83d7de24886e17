#pragma once
// 3D points from rays (thesis section 3.2.2, Algorithm 3.1, and a linear least-squares solution).
// Pose direction: T_world_camera, as the name says (the one exception to geometry/'s camera from
// world): a ray starts at the camera centre in the world, which is that pose's translation.
#include <optional>
#include <vector>

#include "core/geometry.h"

namespace slamcmp {

struct Ray {
  Vec3 origin;     // camera centre, world frame
  Vec3 direction;  // unit, world frame
};

// The ray through undistorted normalised coordinates xy seen from T_world_camera.
Ray rayFromObservation(const SE3& T_world_camera, const Vec2& xy_normalised);

// Closest points of two lines: *on_a on line a nearest to line b and vice versa. False when the
// lines are (nearly) parallel: |sin angle| < 1e-12.
bool closestPointsOfRays(const Ray& a, const Ray& b, Vec3* on_a, Vec3* on_b);

// Thesis Algorithm 3.1: the average over all ray pairs of the midpoint of their closest points
// (an intersection counts as its own midpoint), accumulated one ray at a time (a new ray pairs with
// every earlier one: O(rays so far)).
class RayMidpointAverage {
 public:
  void add(const Ray& ray);
  // Empty with fewer than two non-parallel rays.
  std::optional<Vec3> solve() const;

 private:
  std::vector<Ray> rays_;
  Vec3 total_ = Vec3::Zero();  // sum of the pairs' midpoints
  int pairs_ = 0;              // non-parallel pairs
};

// Linear least squares: the point minimising the sum of squared distances to the rays,
// sum_i (I - d_i d_i^T) (X - c_i) = 0. Accumulates one ray at a time (O(1) per observation).
class RayLeastSquares {
 public:
  void add(const Ray& ray);
  int size() const { return n_; }
  // Empty when the rays do not determine a point (fewer than two, or all parallel).
  std::optional<Vec3> solve() const;
  // RMS distance of the rays from X (same units as the rays' origins).
  double rmsDistance(const Vec3& X) const;

 private:
  Mat3 A_ = Mat3::Zero();
  Vec3 b_ = Vec3::Zero();
  double c_ = 0;  // sum of c_i^T (I - d_i d_i^T) c_i
  int n_ = 0;
};

}  // namespace slamcmp
