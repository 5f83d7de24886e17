#include "monoslam_ekf/ekf_update.h"

#include <Eigen/Cholesky>

namespace slamcmp {

namespace {

// P H^T: H is non-zero only over r, q and each observed point.
Eigen::MatrixXd covarianceTimesHt(const Eigen::MatrixXd& P, const std::vector<PointObservation>& observations) {
  Eigen::MatrixXd PHt(P.rows(), 2 * observations.size());
  for (size_t k = 0; k < observations.size(); ++k) {
    const PointObservation& o = observations[k];
    PHt.middleCols<2>(2 * k) = P.middleCols<3>(EkfState::kR) * o.h.H_r.transpose() +
                               P.middleCols<4>(EkfState::kQ) * o.h.H_q.transpose() +
                               P.middleCols<3>(o.offset) * o.h.H_y.transpose();
  }
  return PHt;
}

// H X from P H^T: S = H (P H^T) + R.
Eigen::MatrixXd stackedHTimes(const std::vector<PointObservation>& observations, const Eigen::MatrixXd& X) {
  Eigen::MatrixXd out(2 * observations.size(), X.cols());
  for (size_t k = 0; k < observations.size(); ++k) {
    const PointObservation& o = observations[k];
    out.middleRows<2>(2 * k) = o.h.H_r * X.middleRows<3>(EkfState::kR) + o.h.H_q * X.middleRows<4>(EkfState::kQ) +
                               o.h.H_y * X.middleRows<3>(o.offset);
  }
  return out;
}

}  // namespace

Eigen::MatrixXd innovationCovariance(const EkfState& state, const std::vector<PointObservation>& observations,
                                     double pixel_sigma) {
  const Eigen::MatrixXd PHt = covarianceTimesHt(state.P(), observations);
  Eigen::MatrixXd S = stackedHTimes(observations, PHt);
  S.diagonal().array() += pixel_sigma * pixel_sigma;
  return 0.5 * (S + S.transpose());
}

void batchUpdate(EkfState& state, const std::vector<PointObservation>& observations, double pixel_sigma) {
  if (observations.empty()) return;
  const int m = static_cast<int>(observations.size());
  const Eigen::MatrixXd PHt = covarianceTimesHt(state.P(), observations);
  Eigen::MatrixXd S = stackedHTimes(observations, PHt);
  S.diagonal().array() += pixel_sigma * pixel_sigma;
  S = 0.5 * (S + S.transpose()).eval();
  Eigen::VectorXd nu(2 * m);
  for (int k = 0; k < m; ++k) nu.segment<2>(2 * k) = observations[k].z - observations[k].h.uv_distorted;
  const Eigen::LDLT<Eigen::MatrixXd> ldlt(S);
  const Eigen::MatrixXd K = ldlt.solve(PHt.transpose()).transpose();  // P H^T S^-1 (S symmetric)
  state.x() += K * nu;
  state.P().noalias() -= K * PHt.transpose();
  state.symmetrise();
  state.renormaliseQuaternion();
}

}  // namespace slamcmp
