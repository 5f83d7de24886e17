#pragma once
// Constant-velocity motion with acceleration impulses (SPEC section 5, Davison et al. 2007 eq. 2):
//   r' = r + (v + V) dt,  q' = q * quat((w + W) dt),  v' = v + V,  w' = w + W,
// with V = a dt, W = alpha dt (MotionModelOptions says how the noise scales with dt), followed
// by the renormalisation of q', whose Jacobian is folded into F_x and F_n.
#include <Eigen/Core>

#include "core/geometry.h"
#include "ekf/ekf_state.h"
#include "ekf/ekf_options.h"

namespace slamcmp {

using CameraVector = Eigen::Matrix<double, 13, 1>;
using Mat13 = Eigen::Matrix<double, 13, 13>;
using Mat13x6 = Eigen::Matrix<double, 13, 6>;

// The camera block after dt seconds with impulses n = (V, W); F_x = d x' / d x, F_n = d x' / d n.
CameraVector predictCamera(const CameraVector& x, double dt, const Eigen::Matrix<double, 6, 1>& n,
                           Mat13* F_x = nullptr, Mat13x6* F_n = nullptr);

// The constant velocities that take the camera from one pose to the next in dt seconds: what
// predictCamera without impulses inverts. v in the world frame, w in the camera's (q' = q *
// quat(w dt)).
struct CameraVelocity {
  Vec3 v_world = Vec3::Zero();
  Vec3 w_camera = Vec3::Zero();
};
CameraVelocity velocityBetween(const SE3& T_world_camera_from, const SE3& T_world_camera_to, double dt);

// Covariance of the impulses n = (V, W): diag(sigma_a^2 I, sigma_alpha^2 I) * dt / reference_rate.
Eigen::Matrix<double, 6, 6> impulseCovariance(const MotionModelOptions& options, double dt);

// The EKF prediction: camera block through predictCamera (zero-mean impulses), P_cc <- F P_cc F^T
// + F_n Q F_n^T, camera-feature cross covariances <- F P_cf; features are static.
void predict(EkfState& state, double dt, const MotionModelOptions& options);

}  // namespace slamcmp
