#include "ekf/inverse_depth.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "ekf/ekf_update.h"

namespace slamcmp {

namespace {

// (theta, phi) of a world-frame ray h: theta = atan2(hx, hz), phi = atan2(-hy, sqrt(hx^2 + hz^2)),
// with d(theta, phi) / d h.
Vec2 azimuthElevation(const Vec3& h, Eigen::Matrix<double, 2, 3>* J) {
  const double xz2 = h.x() * h.x() + h.z() * h.z(), xz = std::sqrt(xz2), n2 = h.squaredNorm();
  *J << h.z() / xz2, 0, -h.x() / xz2,  //
      h.y() * h.x() / (xz * n2), -xz / n2, h.y() * h.z() / (xz * n2);
  return Vec2(std::atan2(h.x(), h.z()), std::atan2(-h.y(), xz));
}

}  // namespace

Vec3 inverseDepthDirection(double theta, double phi, Eigen::Matrix<double, 3, 2>* J) {
  const double ct = std::cos(theta), st = std::sin(theta), cp = std::cos(phi), sp = std::sin(phi);
  if (J) *J << cp * ct, -sp * st, 0, -cp, -cp * st, -sp * ct;
  return Vec3(cp * st, -sp, cp * ct);
}

Vec3 inverseDepthPoint(const Vec6& y, double min_rho) {
  return y.head<3>() + inverseDepthDirection(y(3), y(4)) / std::max(y(5), min_rho);
}

bool predictInverseDepthMeasurement(const CameraModel& camera, const Vec3& r, const Vec4& q, const Vec6& y,
                                    PointMeasurement* out) {
  Eigen::Matrix<double, 3, 2> J_m;
  const Vec3 m = inverseDepthDirection(y(3), y(4), &J_m);
  const double rho = y(5);
  const Vec3 d_world = rho * (y.head<3>() - r) + m;  // the point minus r, scaled by rho
  Mat34 J_q;
  const Vec3 d_camera = rotateByQuatInverse(q, d_world, &J_q);
  if (!(d_camera.z() > 1e-6 * d_world.norm())) return false;
  Mat23 J_p;
  out->uv_distorted = camera.project(d_camera, &J_p);
  out->p_camera = d_camera / std::max(rho, 1e-3);  // as inverseDepthPoint: far, for rho <= 0
  out->row_timed = false;
  const Mat23 J_pw = J_p * rotationFromQuat(q).transpose();  // d h / d d_world
  out->H_r = -rho * J_pw;
  out->H_q = J_p * J_q;
  out->H_y.resize(2, 6);
  out->H_y << rho * J_pw, J_pw * J_m, J_pw * (y.head<3>() - r);
  return true;
}

StateBlock inverseDepthFeature(const EkfState& state, const CameraModel& camera, const Vec2& uv_distorted,
                               double pixel_sigma, double rho0, double rho_sigma) {
  Mat34 J_q;
  Eigen::Matrix<double, 3, 2> J_uv;
  const Vec3 h = rayFromPixel(camera, state.q(), uv_distorted, &J_q, &J_uv);
  Eigen::Matrix<double, 2, 3> J_angles;
  const Vec2 angles = azimuthElevation(h, &J_angles);
  // d y / d(camera state): x0 = r, (theta, phi) through h(q); rho is independent of the state.
  Eigen::Matrix<double, 6, EkfState::kCameraDim> J_x = Eigen::Matrix<double, 6, EkfState::kCameraDim>::Zero();
  J_x.block<3, 3>(0, EkfState::kR) = Mat3::Identity();
  J_x.block<2, 4>(3, EkfState::kQ) = J_angles * J_q;
  const Eigen::MatrixXd P_y_rest = J_x * state.P().topRows<EkfState::kCameraDim>();
  Eigen::Matrix<double, 6, 6> P_y = P_y_rest.leftCols<EkfState::kCameraDim>() * J_x.transpose();
  const Mat2 J_angles_uv = J_angles * J_uv;
  P_y.block<2, 2>(3, 3) += J_angles_uv * J_angles_uv.transpose() * pixel_sigma * pixel_sigma;
  P_y(5, 5) += rho_sigma * rho_sigma;
  Vec6 y;
  y << state.r(), angles, rho0;
  return {y, P_y, P_y_rest};
}

int appendInverseDepthFeature(EkfState& state, const CameraModel& camera, const Vec2& uv_distorted,
                              double pixel_sigma, double rho0, double rho_sigma) {
  const StateBlock block = inverseDepthFeature(state, camera, uv_distorted, pixel_sigma, rho0, rho_sigma);
  // Near the world's vertical axis the azimuth is undefined: its Jacobian grows as 1 / the ray's
  // horizontal part (1 / 0 on the axis). Refused where the pixel's noise alone spans a radian of it.
  if (!(block.P_block(3, 3) < 1.0) || !block.P_block_rest.allFinite()) return -1;
  return state.append(block.value, block.P_block, block.P_block_rest);
}

double linearityIndex(const EkfState& state, int offset) {
  const Vec6 y = state.x().segment<6>(offset);
  const double rho = y(5);
  if (!(rho > 0)) return std::numeric_limits<double>::infinity();
  const Vec3 m = inverseDepthDirection(y(3), y(4));
  const Vec3 h = y.head<3>() + m / rho - state.r();
  const double d1 = h.norm();
  const double sigma_d = std::sqrt(std::max(0.0, state.P()(offset + 5, offset + 5))) / (rho * rho);
  const double L = 4 * sigma_d / d1 * std::abs(m.dot(h) / d1);
  return L >= 0 ? L : std::numeric_limits<double>::infinity();  // the camera on the point (0 / 0): not linear
}

Vec3 inverseDepthToPoint(const Vec6& y, Eigen::Matrix<double, 3, 6>* J) {
  Eigen::Matrix<double, 3, 2> J_m;
  const Vec3 m = inverseDepthDirection(y(3), y(4), &J_m);
  const double rho = y(5);
  *J << Mat3::Identity(), J_m / rho, -m / (rho * rho);
  return y.head<3>() + m / rho;
}

bool constrainMeanInverseDepth(EkfState& state, const std::vector<int>& offsets, double rho0, double sigma) {
  if (offsets.empty()) return false;
  // h = mean(rho_i): H has 1/n at each rho (the 6th of a feature's values), so P H^T is the mean of
  // P's rho columns and H P H^T the mean of that column's rho entries.
  const double n = static_cast<double>(offsets.size());
  Eigen::MatrixXd W = Eigen::MatrixXd::Zero(state.size(), 1);
  double mean_rho = 0;
  for (int offset : offsets) {
    W.col(0) += state.P().col(offset + 5) / n;
    mean_rho += state.x()(offset + 5) / n;
  }
  Eigen::MatrixXd S(1, 1);
  S(0, 0) = sigma * sigma;
  for (int offset : offsets) S(0, 0) += W(offset + 5, 0) / n;
  return kalmanUpdate(state, W, S, Eigen::VectorXd::Constant(1, rho0 - mean_rho));
}

int convertToPoint(EkfState& state, int offset) {
  Eigen::Matrix<double, 3, 6> J;
  const Vec3 p = inverseDepthToPoint(state.x().segment<6>(offset), &J);
  const Eigen::MatrixXd P_rest = J * state.P().middleRows<6>(offset);  // 3 x n
  const Mat3 P_point = P_rest.middleCols<6>(offset) * J.transpose();
  const int point_offset = state.append(p, P_point, P_rest);
  state.remove(offset, 6);
  return point_offset - 6;  // the inverse-depth block was before it
}

}  // namespace slamcmp
