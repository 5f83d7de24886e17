#include "ekf/motion_model.h"

#include <cmath>

namespace slamcmp {

CameraVector predictCamera(const CameraVector& x, double dt, const Eigen::Matrix<double, 6, 1>& n,
                           Mat13* F_x, Mat13x6* F_n) {
  constexpr int R = EkfState::kR, Q = EkfState::kQ, V = EkfState::kV, W = EkfState::kW;
  const Vec3 v = x.segment<3>(V) + n.head<3>();
  const Vec3 w = x.segment<3>(W) + n.tail<3>();
  const Vec4 q = x.segment<4>(Q);
  Mat43 J_dq;  // d quat(w dt) / d(w dt)
  const Vec4 dq = quatFromRotvecJ(w * dt, &J_dq);
  Mat4 J_norm;
  const Vec4 q_raw = quatMultiply(q, dq);
  CameraVector out;
  out.segment<3>(R) = x.segment<3>(R) + v * dt;
  out.segment<4>(Q) = normaliseQuat(q_raw, &J_norm);
  out.segment<3>(V) = v;
  out.segment<3>(W) = w;

  // d q' / d w (= d q' / d W): normalisation * left multiplication by q * d quat / d(w dt) * dt.
  const Mat43 dq_dw = J_norm * quatLeft(q) * J_dq * dt;
  if (F_x) {
    F_x->setIdentity();
    F_x->block<3, 3>(R, V) = Mat3::Identity() * dt;
    F_x->block<4, 4>(Q, Q) = J_norm * quatRight(dq);
    F_x->block<4, 3>(Q, W) = dq_dw;
  }
  if (F_n) {
    F_n->setZero();
    F_n->block<3, 3>(R, 0) = Mat3::Identity() * dt;
    F_n->block<4, 3>(Q, 3) = dq_dw;
    F_n->block<3, 3>(V, 0) = Mat3::Identity();
    F_n->block<3, 3>(W, 3) = Mat3::Identity();
  }
  return out;
}

CameraVelocity velocityBetween(const SE3& T_world_camera_from, const SE3& T_world_camera_to, double dt) {
  return {(T_world_camera_to.t() - T_world_camera_from.t()) / dt,
          rotvecFromRotation(T_world_camera_from.R().transpose() * T_world_camera_to.R()) / dt};
}

Eigen::Matrix<double, 6, 6> impulseCovariance(const MotionModelOptions& options, double dt) {
  Eigen::Matrix<double, 6, 6> Q = Eigen::Matrix<double, 6, 6>::Zero();
  const double scale = std::sqrt(dt / options.reference_rate);  // see MotionModelOptions
  const double sv = options.sigma_a * scale, sw = options.sigma_alpha * scale;
  Q.topLeftCorner<3, 3>() = Mat3::Identity() * sv * sv;
  Q.bottomRightCorner<3, 3>() = Mat3::Identity() * sw * sw;
  return Q;
}

void predict(EkfState& state, double dt, const MotionModelOptions& options) {
  constexpr int C = EkfState::kCameraDim;
  Mat13 F;
  Mat13x6 G;
  const CameraVector x = state.x().head<C>();
  state.x().head<C>() = predictCamera(x, dt, Eigen::Matrix<double, 6, 1>::Zero(), &F, &G);
  Eigen::MatrixXd& P = state.P();
  const int rest = state.size() - C;
  const Mat13 P_cc = P.topLeftCorner<C, C>();
  P.topLeftCorner<C, C>() =
      F * P_cc * F.transpose() + G * impulseCovariance(options, dt) * G.transpose();
  if (rest > 0) {
    P.topRightCorner(C, rest) = (F * P.topRightCorner(C, rest)).eval();
    P.bottomLeftCorner(rest, C) = P.topRightCorner(C, rest).transpose();
  }
}

}  // namespace slamcmp
