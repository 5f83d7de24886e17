#include "geometry/pose_refinement.h"

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

#include "core/error.h"

namespace slamcmp {

void PoseRefinementOptions::check() const {
  if (max_iterations < 0) throw OptionError("max_iterations", "must be >= 0");
  if (huber_px < 0) throw OptionError("huber_px", "must be >= 0");
}

namespace {

// Normal equations of the weighted residuals; returns the weighted cost (pixels^2).
double accumulate(const SE3& T, const std::vector<Vec3>& p_world, const std::vector<Vec2>& xy,
                  double f, double huber, Mat6* H, Vec6* g) {
  if (H) H->setZero();
  if (g) g->setZero();
  double cost = 0;
  for (size_t i = 0; i < p_world.size(); ++i) {
    const Vec3 p = T * p_world[i];
    if (p.z() <= 1e-9) continue;
    const double iz = 1.0 / p.z();
    const Vec2 r = f * (Vec2(p.x() * iz, p.y() * iz) - xy[i]);
    const double e = r.norm();
    double w = 1.0;
    if (huber > 0 && e > huber) w = huber / e;
    cost += huber > 0 && e > huber ? 2 * huber * e - huber * huber : e * e;
    if (!H) continue;
    const Eigen::Matrix<double, 2, 6> J = projectionPoseJacobian(p, f);
    *H += w * J.transpose() * J;
    if (g) *g += w * J.transpose() * r;
  }
  return cost;
}

}  // namespace

SE3 applyPoseDelta(const SE3& T, const Vec6& delta) {
  const Mat3 dR = rotationFromRotvec(delta.head<3>());
  return SE3(nearestRotation(dR * T.R()), dR * T.t() + delta.tail<3>());
}

Eigen::Matrix<double, 2, 6> projectionPoseJacobian(const Vec3& p_camera, double scale) {
  const double iz = 1.0 / p_camera.z();
  Mat23 J_xy_p;  // scale pinholeJacobian(p_camera), the scale applied first as the refinement always did
  J_xy_p << scale * iz, 0, -scale * p_camera.x() * iz * iz, 0, scale * iz, -scale * p_camera.y() * iz * iz;
  Eigen::Matrix<double, 3, 6> J_p_delta;
  J_p_delta << -skew(p_camera), Mat3::Identity();
  return J_xy_p * J_p_delta;
}

Vec6 poseDifference(const SE3& T_to, const SE3& T_from) {
  const Mat3 dR = T_to.R() * T_from.R().transpose();
  Vec6 delta;
  delta << rotvecFromRotation(dR), T_to.t() - dR * T_from.t();
  return delta;
}

Mat6 reprojectionHessian(const SE3& T_camera_world, const std::vector<Vec3>& p_world,
                         const std::vector<Vec2>& xy_normalised, double focal_px) {
  Mat6 H;
  accumulate(T_camera_world, p_world, xy_normalised, focal_px, 0.0, &H, nullptr);
  return H;
}

PoseRefinementResult refinePose(const SE3& T_camera_world, const std::vector<Vec3>& p_world,
                                const std::vector<Vec2>& xy_normalised, double focal_px,
                                const PoseRefinementOptions& options) {
  PoseRefinementResult result{T_camera_world, 0, 0};
  Mat6 H;
  Vec6 g;
  double cost = accumulate(result.T_camera_world, p_world, xy_normalised, focal_px, options.huber_px, &H, &g);
  double lambda = 1e-4;
  bool converged = false;
  for (int it = 0; it < options.max_iterations && !converged; ++it) {
    result.iterations = it + 1;
    bool improved = false;
    for (int attempt = 0; attempt < 8 && !improved; ++attempt) {
      Mat6 A = H;
      A.diagonal() *= 1.0 + lambda;
      const Vec6 delta = A.ldlt().solve(-g);
      if (!delta.allFinite()) break;
      const SE3 candidate = applyPoseDelta(result.T_camera_world, delta);
      const double c = accumulate(candidate, p_world, xy_normalised, focal_px, options.huber_px, nullptr, nullptr);
      if (c < cost) {
        const double gain = cost - c;
        result.T_camera_world = candidate;
        cost = c;
        lambda = std::max(lambda * 0.1, 1e-9);
        improved = true;
        converged = gain < 1e-12 * (1 + cost) || delta.norm() < 1e-12;
      } else {
        lambda *= 10;
      }
    }
    if (!improved) break;
    if (!converged) accumulate(result.T_camera_world, p_world, xy_normalised, focal_px, options.huber_px, &H, &g);
  }
  double sum = 0;
  int n = 0;
  for (double e : reprojectionErrorsPx(result.T_camera_world, p_world, xy_normalised, focal_px))
    if (std::isfinite(e)) sum += e * e, ++n;
  result.rms_px = n ? std::sqrt(sum / n) : 0.0;
  return result;
}

std::vector<double> reprojectionErrorsPx(const SE3& T_camera_world, const std::vector<Vec3>& p_world,
                                         const std::vector<Vec2>& xy_normalised, double focal_px) {
  std::vector<double> errors(p_world.size(), std::numeric_limits<double>::infinity());
  for (size_t i = 0; i < p_world.size(); ++i) {
    const Vec3 p = T_camera_world * p_world[i];
    if (p.z() <= 1e-9) continue;
    errors[i] = focal_px * (Vec2(p.x() / p.z(), p.y() / p.z()) - xy_normalised[i]).norm();
  }
  return errors;
}

}  // namespace slamcmp
