#include "ekf/ekf_state.h"

#include <cassert>

namespace slamcmp {

void EkfState::reset(const SE3& T_world_camera, const Eigen::Matrix<double, 13, 13>& P_camera) {
  x_ = Eigen::VectorXd::Zero(kCameraDim);
  x_.segment<3>(kR) = T_world_camera.t();
  x_.segment<4>(kQ) = quatVector(T_world_camera.quat());
  P_ = P_camera;
}

SE3 EkfState::T_world_camera() const { return SE3(quatFromVector(q()), r()); }

int EkfState::append(const Eigen::VectorXd& value, const Eigen::MatrixXd& P_block,
                     const Eigen::MatrixXd& P_block_rest) {
  const int n = size(), d = static_cast<int>(value.size());
  assert(P_block.rows() == d && P_block.cols() == d);
  assert(P_block_rest.rows() == d && P_block_rest.cols() == n);
  x_.conservativeResize(n + d);
  x_.tail(d) = value;
  P_.conservativeResize(n + d, n + d);
  P_.bottomLeftCorner(d, n) = P_block_rest;
  P_.topRightCorner(n, d) = P_block_rest.transpose();
  P_.bottomRightCorner(d, d) = P_block;
  return n;
}

void EkfState::remove(int offset, int dim) {
  const int n = size();
  assert(offset >= kCameraDim && offset + dim <= n);
  const int tail = n - offset - dim;
  x_.segment(offset, tail) = x_.tail(tail).eval();
  x_.conservativeResize(n - dim);
  // Shift the rows, then the columns, over the removed block.
  P_.middleRows(offset, tail) = P_.bottomRows(tail).eval();
  P_.middleCols(offset, tail) = P_.rightCols(tail).eval();
  P_.conservativeResize(n - dim, n - dim);
}

void EkfState::renormaliseQuaternion() {
  Mat4 J;
  x_.segment<4>(kQ) = normaliseQuat(q(), &J);
  P_.middleRows<4>(kQ) = (J * P_.middleRows<4>(kQ)).eval();
  P_.middleCols<4>(kQ) = (P_.middleCols<4>(kQ) * J.transpose()).eval();
}

}  // namespace slamcmp
