#include "ekf/ekf_update.h"

#include <algorithm>

#include <Eigen/Cholesky>
#include <Eigen/QR>

namespace slamcmp {

namespace {

constexpr int kPose = 7;  // r and q: the camera entries a measurement depends on (offsets 0..6)
using Mat27 = Eigen::Matrix<double, 2, kPose>;

Mat27 poseJacobian(const PointMeasurement& h) {
  Mat27 H;
  H << h.H_r, h.H_q;
  return H;
}

int featureDim(const PointObservation& o) { return o.offset == kKnownPoint ? 0 : static_cast<int>(o.h.H_y.cols()); }

// P H^T (n x 2) of one observation: H is non-zero only over (r, q) and the feature's block.
Eigen::Matrix<double, Eigen::Dynamic, 2> gainNumerator(const Eigen::MatrixXd& P, const PointObservation& o) {
  Eigen::Matrix<double, Eigen::Dynamic, 2> W = P.leftCols<kPose>() * poseJacobian(o.h).transpose();
  if (const int d = featureDim(o)) W.noalias() += P.middleCols(o.offset, d) * o.h.H_y.transpose();
  return W;
}

// H w for the rows of W = P H^T (or any n-row matrix) that H touches.
Eigen::Matrix<double, 2, Eigen::Dynamic> applyH(const PointObservation& o, const Eigen::Ref<const Eigen::MatrixXd>& W) {
  Eigen::Matrix<double, 2, Eigen::Dynamic> out = poseJacobian(o.h) * W.topRows<kPose>();
  if (const int d = featureDim(o)) out.noalias() += o.h.H_y * W.middleRows(o.offset, d);
  return out;
}

// W = P H^T (n x 2m), S = H (P H^T) + R from the rows of W that H touches, nu = z - h.
void gainInnovation(const Eigen::MatrixXd& P, const std::vector<PointObservation>& observations, double pixel_sigma,
                    Eigen::MatrixXd* W, Eigen::MatrixXd* S, Eigen::VectorXd* nu) {
  const int m = static_cast<int>(observations.size());
  W->resize(P.rows(), 2 * m);
  for (int k = 0; k < m; ++k) W->middleCols<2>(2 * k) = gainNumerator(P, observations[k]);
  S->resize(2 * m, 2 * m);
  for (int k = 0; k < m; ++k) S->middleRows<2>(2 * k) = applyH(observations[k], *W);
  S->diagonal().array() += pixel_sigma * pixel_sigma;
  nu->resize(2 * m);
  for (int k = 0; k < m; ++k) nu->segment<2>(2 * k) = observations[k].z - observations[k].h.uv_distorted;
}

}  // namespace

Mat2 pointInnovationCovariance(const EkfState& state, const PointMeasurement& h, int offset, double pixel_sigma) {
  static_assert(EkfState::kR == 0 && EkfState::kQ == 3, "r and q are the first 7 entries");
  const Eigen::MatrixXd& P = state.P();
  const Mat27 H_c = poseJacobian(h);
  Mat2 S = H_c * P.topLeftCorner<kPose, kPose>() * H_c.transpose();
  if (offset != kKnownPoint) {
    const int d = static_cast<int>(h.H_y.cols());
    const Mat2 cross = H_c * P.block(0, offset, kPose, d) * h.H_y.transpose();
    S += h.H_y * P.block(offset, offset, d, d) * h.H_y.transpose() + cross + cross.transpose();
  }
  S.diagonal().array() += pixel_sigma * pixel_sigma;
  return 0.5 * (S + S.transpose());
}

Eigen::MatrixXd innovationCovariance(const EkfState& state, const std::vector<PointObservation>& observations,
                                     double pixel_sigma) {
  // P restricted to (r, q, y_1..y_m) and H over the same entries: S = H_sub P_sub H_sub^T + R
  // (a known point has no block: it is exact).
  const int m = static_cast<int>(observations.size());
  const Eigen::MatrixXd& P = state.P();
  std::vector<int> index;
  for (int i = 0; i < kPose; ++i) index.push_back(i);
  std::vector<int> column(m);  // observation k's first column in H_sub
  for (int k = 0; k < m; ++k) {
    column[k] = static_cast<int>(index.size());
    for (int i = 0; i < featureDim(observations[k]); ++i) index.push_back(observations[k].offset + i);
  }
  const int d = static_cast<int>(index.size());
  const Eigen::MatrixXd P_sub = P(index, index);
  Eigen::MatrixXd H_sub = Eigen::MatrixXd::Zero(2 * m, d);
  for (int k = 0; k < m; ++k) {
    H_sub.block<2, kPose>(2 * k, 0) = poseJacobian(observations[k].h);
    if (const int dim = featureDim(observations[k])) H_sub.block(2 * k, column[k], 2, dim) = observations[k].h.H_y;
  }
  Eigen::MatrixXd S = H_sub * P_sub * H_sub.transpose();
  S.diagonal().array() += pixel_sigma * pixel_sigma;
  return 0.5 * (S + S.transpose());
}

bool kalmanUpdate(EkfState& state, Eigen::MatrixXd W, const Eigen::MatrixXd& S, Eigen::VectorXd nu) {
  const Eigen::LLT<Eigen::MatrixXd> llt(S.selfadjointView<Eigen::Lower>());
  if (llt.info() != Eigen::Success) return false;
  llt.matrixL().solveInPlace(nu);                           // L^-1 nu
  llt.matrixU().solveInPlace<Eigen::OnTheRight>(W);          // W <- P H^T L^-T (U = L^T)
  state.x().noalias() += W * nu;                     // K nu = P H^T S^-1 nu
  Eigen::MatrixXd& P = state.P();
  P.selfadjointView<Eigen::Lower>().rankUpdate(W, -1.0);  // P -= K S K^T = W W^T
  for (int j = 1; j < state.size(); ++j) P.col(j).head(j) = P.row(j).head(j).transpose();
  state.renormaliseQuaternion();
  return true;
}

bool batchUpdate(EkfState& state, const std::vector<PointObservation>& observations, double pixel_sigma) {
  if (observations.empty()) return true;
  Eigen::MatrixXd W, S;
  Eigen::VectorXd nu;
  gainInnovation(state.P(), observations, pixel_sigma, &W, &S, &nu);
  return kalmanUpdate(state, std::move(W), S, std::move(nu));
}

bool iteratedUpdate(EkfState& state, std::vector<PointObservation>* observations, double pixel_sigma,
                    const Relinearise& relinearise, int max_iterations, double tolerance) {
  if (observations->empty()) return true;
  max_iterations = std::max(max_iterations, 1);
  const int m = static_cast<int>(observations->size());
  Eigen::VectorXd iterate = state.x();  // x_i (P stays the prior's)
  Eigen::MatrixXd W, S;
  Eigen::VectorXd nu;
  Eigen::LLT<Eigen::MatrixXd> llt;
  for (int i = 0; i < max_iterations; ++i) {
    if (i > 0 && !relinearise(iterate, observations)) return false;
    gainInnovation(state.P(), *observations, pixel_sigma, &W, &S, &nu);
    // nu_i = z - h(x_i) - H_i (x_0 - x_i)
    const Eigen::VectorXd dx = state.x() - iterate;
    for (int k = 0; k < m; ++k) nu.segment<2>(2 * k) -= applyH((*observations)[k], dx);
    llt.compute(S.selfadjointView<Eigen::Lower>());
    if (llt.info() != Eigen::Success) return false;
    const Eigen::VectorXd next = state.x() + W * llt.solve(nu);
    const double step = (next.head<kPose>() - iterate.head<kPose>()).lpNorm<Eigen::Infinity>();
    iterate = next;
    if (step < tolerance) break;
  }
  // P -= K_i S_i K_i^T = W S^-1 W^T, as in batchUpdate.
  Eigen::MatrixXd& P = state.P();
  // The QR below needs at least kPose rows (2m > 7); fewer corners never reach an update.
  const bool camera_only = 2 * m > kPose && std::all_of(observations->begin(), observations->end(),
                                                         [](const PointObservation& o) { return featureDim(o) == 0; });
  if (camera_only) {
    // Known points (the board's corners): W = P_c H^T with P_c = P's (r, q) columns, so
    // W S^-1 W^T = P_c H^T S^-1 H P_c^T; with L^-1 H = Q R (R 7x7), that is (P_c R^T)(P_c R^T)^T, a
    // rank-7 update where W's is rank 2m (the rows compressed by QR, as Mourikis and Roumeliotis
    // 2007 compress an MSCKF update). H is the last iteration's, the one S = L L^T was formed with.
    Eigen::MatrixXd H_white(2 * m, kPose);
    for (int k = 0; k < m; ++k) H_white.middleRows<2>(2 * k) = poseJacobian((*observations)[k].h);
    llt.matrixL().solveInPlace(H_white);  // L^-1 H
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(H_white);
    const Eigen::Matrix<double, kPose, kPose> R = qr.matrixQR().topRows<kPose>().triangularView<Eigen::Upper>();
    W = P.leftCols<kPose>() * R.transpose();
  } else {
    llt.matrixU().solveInPlace<Eigen::OnTheRight>(W);
  }
  state.x() = iterate;
  P.selfadjointView<Eigen::Lower>().rankUpdate(W, -1.0);
  for (int j = 1; j < state.size(); ++j) P.col(j).head(j) = P.row(j).head(j).transpose();
  state.renormaliseQuaternion();
  relinearise(state.x(), observations);  // the update's residuals (h where it can be predicted)
  return true;
}

Eigen::VectorXd stateCorrection(const EkfState& state, const std::vector<PointObservation>& observations,
                                double pixel_sigma) {
  Eigen::MatrixXd W, S;
  Eigen::VectorXd nu;
  gainInnovation(state.P(), observations, pixel_sigma, &W, &S, &nu);
  const Eigen::LLT<Eigen::MatrixXd> llt(S.selfadjointView<Eigen::Lower>());
  if (llt.info() != Eigen::Success) return Eigen::VectorXd::Zero(state.size());
  return W * llt.solve(nu);
}

}  // namespace slamcmp
