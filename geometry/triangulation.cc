#include "geometry/triangulation.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>

namespace slamcmp {

Ray rayFromObservation(const SE3& T_world_camera, const Vec2& xy_normalised) {
  return {T_world_camera.t(), (T_world_camera.R() * xy_normalised.homogeneous()).normalized()};
}

bool closestPointsOfRays(const Ray& a, const Ray& b, Vec3* on_a, Vec3* on_b) {
  // Minimise |a.o + s a.d - b.o - u b.d|^2 over (s, u) (unit directions).
  const Vec3 w = a.origin - b.origin;
  const double c = a.direction.dot(b.direction);
  const double denom = 1.0 - c * c;  // sin^2 of the angle
  if (denom < 1e-24) return false;
  const double da = a.direction.dot(w), db = b.direction.dot(w);
  const double s = (c * db - da) / denom;
  const double u = (db - c * da) / denom;
  *on_a = a.origin + s * a.direction;
  *on_b = b.origin + u * b.direction;
  return true;
}

void RayMidpointAverage::add(const Ray& ray) {
  for (const Ray& earlier : rays_) {
    Vec3 r1, r2;
    if (!closestPointsOfRays(earlier, ray, &r1, &r2)) continue;  // parallel: no information
    total_ += 0.5 * (r1 + r2);  // equals the intersection when the lines meet
    ++pairs_;
  }
  rays_.push_back(ray);
}

std::optional<Vec3> RayMidpointAverage::solve() const {
  if (pairs_ == 0) return std::nullopt;
  return Vec3(total_ / pairs_);
}

void RayLeastSquares::add(const Ray& ray) {
  const Mat3 P = Mat3::Identity() - ray.direction * ray.direction.transpose();
  A_ += P;
  b_ += P * ray.origin;
  c_ += ray.origin.dot(P * ray.origin);
  ++n_;
}

std::optional<Vec3> RayLeastSquares::solve() const {
  if (n_ < 2) return std::nullopt;
  // A is symmetric positive semi-definite; singular when all rays are parallel.
  Eigen::SelfAdjointEigenSolver<Mat3> eig(A_);
  if (eig.eigenvalues()(0) < 1e-12 * std::max(1.0, eig.eigenvalues()(2))) return std::nullopt;
  return Vec3(A_.ldlt().solve(b_));
}

double RayLeastSquares::rmsDistance(const Vec3& X) const {
  if (n_ == 0) return 0;
  const double sum = X.dot(A_ * X) - 2 * b_.dot(X) + c_;
  return std::sqrt(std::max(0.0, sum) / n_);
}

}  // namespace slamcmp
