#include "ekf/ekf_state.h"

#include <cassert>

namespace slamcmp {

Eigen::Matrix<double, 13, 13> cameraCovariance(double sigma_r, double sigma_q, double sigma_v, double sigma_w) {
  Eigen::Matrix<double, 13, 13> P = Eigen::Matrix<double, 13, 13>::Zero();
  P.diagonal() << Vec3::Constant(sigma_r * sigma_r), Vec4::Constant(sigma_q * sigma_q),
      Vec3::Constant(sigma_v * sigma_v), Vec3::Constant(sigma_w * sigma_w);
  return P;
}

void EkfState::reset(const SE3& T_world_camera, const Eigen::Matrix<double, 13, 13>& P_camera) {
  x_ = Eigen::VectorXd::Zero(kCameraDim);
  x_.segment<3>(kR) = T_world_camera.t();
  x_.segment<4>(kQ) = quatVector(T_world_camera.quat());
  P_ = P_camera;
  tail_ = 0;
}

SE3 EkfState::T_world_camera() const { return SE3(quatFromVector(q()), r()); }

int EkfState::append(const Eigen::VectorXd& value, const Eigen::MatrixXd& P_block,
                     const Eigen::MatrixXd& P_block_rest) {
  const int at = size() - tail_;
  appendToTail(value, P_block, P_block_rest);
  tail_ -= static_cast<int>(value.size());
  if (tail_ == 0) return at;
  // Rotate the new block in front of the tail: x = (head, tail, new) -> (head, new, tail).
  const int n = size(), d = static_cast<int>(value.size());
  Eigen::VectorXi order(n);
  for (int i = 0; i < at; ++i) order[i] = i;
  for (int i = 0; i < d; ++i) order[at + i] = n - d + i;
  for (int i = 0; i < tail_; ++i) order[at + d + i] = at + i;
  const Eigen::PermutationMatrix<Eigen::Dynamic> to_old(order);  // new index i <- old index order[i]
  x_ = to_old.transpose() * x_;
  P_ = (to_old.transpose() * P_ * to_old).eval();
  return at;
}

int EkfState::appendToTail(const Eigen::VectorXd& value, const Eigen::MatrixXd& P_block,
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
  tail_ += d;
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
  if (offset >= n - tail_) tail_ -= dim;
}

void EkfState::renormaliseQuaternion(int offset) {
  Mat4 J;
  x_.segment<4>(offset) = normaliseQuat(x_.segment<4>(offset), &J);
  P_.middleRows<4>(offset) = (J * P_.middleRows<4>(offset)).eval();
  P_.middleCols<4>(offset) = (P_.middleCols<4>(offset) * J.transpose()).eval();
}

}  // namespace slamcmp
