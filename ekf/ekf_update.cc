#include "ekf/ekf_update.h"

#include <Eigen/Cholesky>

namespace slamcmp {

namespace {

constexpr int kPose = 7;  // r and q: the camera entries a measurement depends on (offsets 0..6)
using Mat27 = Eigen::Matrix<double, 2, kPose>;

Mat27 poseJacobian(const PointMeasurement& h) {
  Mat27 H;
  H << h.H_r, h.H_q;
  return H;
}

}  // namespace

Mat2 pointInnovationCovariance(const EkfState& state, const PointMeasurement& h, int offset, double pixel_sigma) {
  static_assert(EkfState::kR == 0 && EkfState::kQ == 3, "r and q are the first 7 entries");
  const Eigen::MatrixXd& P = state.P();
  const Mat27 H_c = poseJacobian(h);
  if (offset == kKnownPoint) {
    Mat2 S = H_c * P.topLeftCorner<kPose, kPose>() * H_c.transpose();
    S.diagonal().array() += pixel_sigma * pixel_sigma;
    return 0.5 * (S + S.transpose());
  }
  const Eigen::Matrix<double, 2, 3> H_c_P_cy = H_c * P.block<kPose, 3>(0, offset);
  Mat2 S = H_c * P.topLeftCorner<kPose, kPose>() * H_c.transpose() +
           h.H_y * P.block<3, 3>(offset, offset) * h.H_y.transpose();
  const Mat2 cross = H_c_P_cy * h.H_y.transpose();
  S += cross + cross.transpose();
  S.diagonal().array() += pixel_sigma * pixel_sigma;
  return 0.5 * (S + S.transpose());
}

Eigen::MatrixXd innovationCovariance(const EkfState& state, const std::vector<PointObservation>& observations,
                                     double pixel_sigma) {
  // P restricted to (r, q, y_1..y_m) and H over the same entries: S = H_sub P_sub H_sub^T + R
  // (a known point's y block stays zero: it is exact).
  const int m = static_cast<int>(observations.size()), d = kPose + 3 * m;
  const Eigen::MatrixXd& P = state.P();
  std::vector<int> index(d, -1);
  for (int i = 0; i < kPose; ++i) index[i] = i;
  for (int k = 0; k < m; ++k)
    for (int i = 0; i < 3; ++i)
      if (observations[k].offset != kKnownPoint) index[kPose + 3 * k + i] = observations[k].offset + i;
  Eigen::MatrixXd P_sub(d, d);
  for (int j = 0; j < d; ++j)
    for (int i = 0; i < d; ++i) P_sub(i, j) = index[i] < 0 || index[j] < 0 ? 0.0 : P(index[i], index[j]);
  Eigen::MatrixXd H_sub = Eigen::MatrixXd::Zero(2 * m, d);
  for (int k = 0; k < m; ++k) {
    H_sub.block<2, kPose>(2 * k, 0) = poseJacobian(observations[k].h);
    H_sub.block<2, 3>(2 * k, kPose + 3 * k) = observations[k].h.H_y;
  }
  Eigen::MatrixXd S = H_sub * P_sub * H_sub.transpose();
  S.diagonal().array() += pixel_sigma * pixel_sigma;
  return 0.5 * (S + S.transpose());
}

bool batchUpdate(EkfState& state, const std::vector<PointObservation>& observations, double pixel_sigma) {
  if (observations.empty()) return true;
  const int m = static_cast<int>(observations.size()), n = state.size();
  Eigen::MatrixXd& P = state.P();
  // P H^T (n x 2m): H is non-zero only over (r, q) and each observed point.
  Eigen::MatrixXd W(n, 2 * m);
  for (int k = 0; k < m; ++k) {
    const PointObservation& o = observations[k];
    W.middleCols<2>(2 * k).noalias() = P.leftCols<kPose>() * poseJacobian(o.h).transpose();
    if (o.offset != kKnownPoint) W.middleCols<2>(2 * k).noalias() += P.middleCols<3>(o.offset) * o.h.H_y.transpose();
  }
  // S = H (P H^T) + R from the rows of P H^T that H touches.
  Eigen::MatrixXd S(2 * m, 2 * m);
  for (int k = 0; k < m; ++k) {
    const PointObservation& o = observations[k];
    S.middleRows<2>(2 * k).noalias() = poseJacobian(o.h) * W.topRows<kPose>();
    if (o.offset != kKnownPoint) S.middleRows<2>(2 * k).noalias() += o.h.H_y * W.middleRows<3>(o.offset);
  }
  S.diagonal().array() += pixel_sigma * pixel_sigma;
  Eigen::VectorXd nu(2 * m);
  for (int k = 0; k < m; ++k) nu.segment<2>(2 * k) = observations[k].z - observations[k].h.uv_distorted;

  const Eigen::LLT<Eigen::MatrixXd> llt(S.selfadjointView<Eigen::Lower>());
  if (llt.info() != Eigen::Success) return false;
  llt.matrixL().solveInPlace(nu);                           // L^-1 nu
  llt.matrixU().solveInPlace<Eigen::OnTheRight>(W);          // W <- P H^T L^-T (U = L^T)
  state.x().noalias() += W * nu;                     // K nu = P H^T S^-1 nu
  P.selfadjointView<Eigen::Lower>().rankUpdate(W, -1.0);  // P -= K S K^T = W W^T
  for (int j = 1; j < n; ++j) P.col(j).head(j) = P.row(j).head(j).transpose();
  state.renormaliseQuaternion();
  return true;
}

}  // namespace slamcmp
