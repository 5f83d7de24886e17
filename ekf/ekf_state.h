#pragma once
// The EKF state x = (r, q, v, w, feature blocks...) and its full covariance P (SPEC section 5).
// Camera: position r (world), unit quaternion q = (w, x, y, z) of R_world_camera, linear velocity v
// (world, m/s), angular velocity w (camera frame, rad/s): 13 values. Feature blocks follow in the
// order they were appended (3 for a point, 6 for an initialising ray or an inverse-depth feature);
// removing one removes its rows and columns. A tail of other blocks (a back-end's cloned camera poses and tracked points)
// may follow the features.
#include <Eigen/Core>

#include "core/geometry.h"
#include "ekf/quaternion_jacobians.h"

namespace slamcmp {

// A block to add to the state: its value, covariance and cross covariance with the state before
// it is added (block rows x size()).
struct StateBlock {
  Eigen::VectorXd value;
  Eigen::MatrixXd P_block;
  Eigen::MatrixXd P_block_rest;
};

// The camera block's covariance for independent stds of its position (m), quaternion components,
// velocity (m/s) and angular velocity (rad/s): a start's, a restart's, a relocation's.
Eigen::Matrix<double, 13, 13> cameraCovariance(double sigma_r, double sigma_q, double sigma_v, double sigma_w);

class EkfState {
 public:
  static constexpr int kCameraDim = 13;
  static constexpr int kR = 0, kQ = 3, kV = 7, kW = 10;  // offsets inside the camera block

  // A state holding only the camera, at rest, with covariance P_camera.
  void reset(const SE3& T_world_camera, const Eigen::Matrix<double, 13, 13>& P_camera);

  int size() const { return static_cast<int>(x_.size()); }
  const Eigen::VectorXd& x() const { return x_; }
  const Eigen::MatrixXd& P() const { return P_; }
  Eigen::VectorXd& x() { return x_; }
  Eigen::MatrixXd& P() { return P_; }

  Vec3 r() const { return x_.segment<3>(kR); }
  Vec4 q() const { return x_.segment<4>(kQ); }
  Vec3 v() const { return x_.segment<3>(kV); }
  Vec3 w() const { return x_.segment<3>(kW); }
  SE3 T_world_camera() const;

  // Appends a block with value `value`, covariance `P_block` and cross covariance `P_block_rest`
  // (block rows x size() before the append) with everything already in the state, before the
  // tail. Returns its offset.
  int append(const Eigen::VectorXd& value, const Eigen::MatrixXd& P_block,
             const Eigen::MatrixXd& P_block_rest);
  // The same at the very end, in the tail: blocks that are not the map's (past camera poses
  // cloned for a sliding window, points of tracked features), addressed from the tail's start, so
  // that the map's features can come and go before them.
  int appendToTail(const Eigen::VectorXd& value, const Eigen::MatrixXd& P_block,
                   const Eigen::MatrixXd& P_block_rest);
  int tailSize() const { return tail_; }
  // Removes `dim` rows and columns starting at `offset` (a feature block or a tail block, never
  // the camera).
  void remove(int offset, int dim);

  // q <- q / |q| with the normalisation Jacobian applied to P's quaternion rows and columns: the
  // camera's, or the one at `offset` (a cloned pose's).
  void renormaliseQuaternion(int offset = kQ);

 private:
  Eigen::VectorXd x_;
  Eigen::MatrixXd P_;
  int tail_ = 0;  // dimension of the tail's blocks
};

}  // namespace slamcmp
