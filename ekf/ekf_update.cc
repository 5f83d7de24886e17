#include "ekf/ekf_update.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace slamcmp {

namespace {

constexpr int kPose = 7;     // r and q: the camera entries a measurement depends on (offsets 0..6)
constexpr int kMoving = 13;  // and v, w for one seen at its row's time (PointMeasurement::row_timed)

// d h / d camera over its first kCam entries (a frame-time observation in a batch with row-timed
// ones: zero over v and w).
template <int kCam>
Eigen::Matrix<double, 2, kCam> cameraJacobian(const PointMeasurement& h) {
  Eigen::Matrix<double, 2, kCam> H;
  if constexpr (kCam == kPose) H << h.H_r, h.H_q;
  else if (h.row_timed) H << h.H_r, h.H_q, h.H_v, h.H_w;
  else H << h.H_r, h.H_q, Mat23::Zero(), Mat23::Zero();
  return H;
}

bool anyRowTimed(const std::vector<PointObservation>& observations) {
  return std::any_of(observations.begin(), observations.end(), [](const PointObservation& o) { return o.h.row_timed; });
}

int featureDim(const PointObservation& o) { return o.offset == kKnownPoint ? 0 : static_cast<int>(o.h.H_y.cols()); }

// P H^T (n x 2) of one observation: H is non-zero only over the camera's first kCam entries and the
// feature's block.
template <int kCam>
Eigen::Matrix<double, Eigen::Dynamic, 2> gainNumerator(const Eigen::MatrixXd& P, const PointObservation& o) {
  Eigen::Matrix<double, Eigen::Dynamic, 2> W = P.leftCols<kCam>() * cameraJacobian<kCam>(o.h).transpose();
  if (const int d = featureDim(o)) W.noalias() += P.middleCols(o.offset, d) * o.h.H_y.transpose();
  return W;
}

// H w for the rows of W = P H^T (or any n-row matrix) that H touches.
template <int kCam>
Eigen::Matrix<double, 2, Eigen::Dynamic> applyH(const PointObservation& o, const Eigen::Ref<const Eigen::MatrixXd>& W) {
  Eigen::Matrix<double, 2, Eigen::Dynamic> out = cameraJacobian<kCam>(o.h) * W.topRows<kCam>();
  if (const int d = featureDim(o)) out.noalias() += o.h.H_y * W.middleRows(o.offset, d);
  return out;
}

// W = P H^T (n x 2m), S = H (P H^T) + R from the rows of W that H touches, and nu = z - h when asked.
template <int kCam>
void gainInnovationOver(const Eigen::MatrixXd& P, const std::vector<PointObservation>& observations, double pixel_sigma,
                        Eigen::MatrixXd* W, Eigen::MatrixXd* S, Eigen::VectorXd* nu) {
  const int m = static_cast<int>(observations.size());
  W->resize(P.rows(), 2 * m);
  for (int k = 0; k < m; ++k) W->middleCols<2>(2 * k) = gainNumerator<kCam>(P, observations[k]);
  S->resize(2 * m, 2 * m);
  for (int k = 0; k < m; ++k) S->middleRows<2>(2 * k) = applyH<kCam>(observations[k], *W);
  S->diagonal().array() += pixel_sigma * pixel_sigma;
  if (!nu) return;
  nu->resize(2 * m);
  for (int k = 0; k < m; ++k) nu->segment<2>(2 * k) = observations[k].z - observations[k].h.uv_distorted;
}

void gainInnovation(const Eigen::MatrixXd& P, const std::vector<PointObservation>& observations, double pixel_sigma,
                    Eigen::MatrixXd* W, Eigen::MatrixXd* S, Eigen::VectorXd* nu) {
  if (anyRowTimed(observations)) gainInnovationOver<kMoving>(P, observations, pixel_sigma, W, S, nu);
  else gainInnovationOver<kPose>(P, observations, pixel_sigma, W, S, nu);
}

// P -= W W^T, a symmetric rank update of P's lower triangle mirrored to the upper (P stays exactly
// symmetric), then q renormalised with its Jacobian applied to P.
void downdate(EkfState& state, const Eigen::MatrixXd& W) {
  Eigen::MatrixXd& P = state.P();
  P.selfadjointView<Eigen::Lower>().rankUpdate(W, -1.0);
  for (int j = 1; j < state.size(); ++j) P.col(j).head(j) = P.row(j).head(j).transpose();
  state.renormaliseQuaternion();
}

template <int kCam>
Mat2 pointInnovationCovarianceOver(const EkfState& state, const PointMeasurement& h, int offset, double pixel_sigma) {
  static_assert(EkfState::kR == 0 && EkfState::kQ == 3 && EkfState::kV == 7 && EkfState::kW == 10,
                "r, q, v, w are the first 13 entries");
  const Eigen::MatrixXd& P = state.P();
  const Eigen::Matrix<double, 2, kCam> H_c = cameraJacobian<kCam>(h);
  Mat2 S = H_c * P.topLeftCorner<kCam, kCam>() * H_c.transpose();
  if (offset != kKnownPoint) {
    const int d = static_cast<int>(h.H_y.cols());
    const Mat2 cross = H_c * P.block(0, offset, kCam, d) * h.H_y.transpose();
    S += h.H_y * P.block(offset, offset, d, d) * h.H_y.transpose() + cross + cross.transpose();
  }
  S.diagonal().array() += pixel_sigma * pixel_sigma;
  return 0.5 * (S + S.transpose());
}

}  // namespace

Mat2 pointInnovationCovariance(const EkfState& state, const PointMeasurement& h, int offset, double pixel_sigma) {
  return h.row_timed ? pointInnovationCovarianceOver<kMoving>(state, h, offset, pixel_sigma)
                     : pointInnovationCovarianceOver<kPose>(state, h, offset, pixel_sigma);
}

Eigen::MatrixXd innovationCovariance(const EkfState& state, const std::vector<PointObservation>& observations,
                                     double pixel_sigma) {
  // P restricted to (r, q[, v, w], y_1..y_m) and H over the same entries: S = H_sub P_sub H_sub^T + R
  // (a known point has no block: it is exact).
  const int m = static_cast<int>(observations.size());
  const Eigen::MatrixXd& P = state.P();
  const bool moving = anyRowTimed(observations);
  std::vector<int> index;
  for (int i = 0; i < (moving ? kMoving : kPose); ++i) index.push_back(i);
  std::vector<int> column(m);  // observation k's first column in H_sub
  for (int k = 0; k < m; ++k) {
    column[k] = static_cast<int>(index.size());
    for (int i = 0; i < featureDim(observations[k]); ++i) index.push_back(observations[k].offset + i);
  }
  const int d = static_cast<int>(index.size());
  const Eigen::MatrixXd P_sub = P(index, index);
  Eigen::MatrixXd H_sub = Eigen::MatrixXd::Zero(2 * m, d);
  for (int k = 0; k < m; ++k) {
    if (moving) H_sub.block<2, kMoving>(2 * k, 0) = cameraJacobian<kMoving>(observations[k].h);
    else H_sub.block<2, kPose>(2 * k, 0) = cameraJacobian<kPose>(observations[k].h);
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
  downdate(state, W);                                // P -= K S K^T = W W^T
  return true;
}

bool orientationUpdate(EkfState& state, const Mat3& R_world_camera, double sigma_rad) {
  // h(q) = H q is odd in q, so q and -q (one rotation) give the same update.
  const Eigen::Matrix<double, 3, 4> H = 2.0 * quatLeft(quatVector(Quat(R_world_camera).conjugate())).bottomRows<3>();
  const Vec3 h = H * state.q();
  const int kQ = EkfState::kQ;
  Eigen::MatrixXd W = state.P().middleCols<4>(kQ) * H.transpose();
  const Eigen::MatrixXd S = H * W.middleRows<4>(kQ) + Mat3::Identity() * (sigma_rad * sigma_rad);
  return kalmanUpdate(state, std::move(W), S, -h);
}

bool batchUpdate(EkfState& state, const std::vector<PointObservation>& observations, double pixel_sigma) {
  if (observations.empty()) return true;
  Eigen::MatrixXd W, S;
  Eigen::VectorXd nu;
  gainInnovation(state.P(), observations, pixel_sigma, &W, &S, &nu);
  return kalmanUpdate(state, std::move(W), S, std::move(nu));
}

namespace {

bool knownPointsOnly(const std::vector<PointObservation>& observations) {
  return std::all_of(observations.begin(), observations.end(),
                     [](const PointObservation& o) { return featureDim(o) == 0; });
}

// Gauss-Newton on the prior and the measurements: x_{i+1} = x_0 + correct(nu_i) with
// nu_i = z - h(x_i) - H_i (x_0 - x_i), until the camera moves by less than `tolerance`. `correct`
// forms its gain at the observations' current linearisation (false: S is not positive definite).
template <int kCam, class Correct>
bool gaussNewton(const EkfState& state, std::vector<PointObservation>* observations, const Relinearise& relinearise,
                 int max_iterations, double tolerance, const Correct& correct, Eigen::VectorXd* iterate) {
  const int m = static_cast<int>(observations->size());
  *iterate = state.x();
  for (int i = 0; i < std::max(max_iterations, 1); ++i) {
    if (i > 0 && !relinearise(*iterate, observations)) return false;
    Eigen::VectorXd nu(2 * m);
    const Eigen::VectorXd dx = state.x() - *iterate;
    for (int k = 0; k < m; ++k) {
      const PointObservation& o = (*observations)[k];
      nu.segment<2>(2 * k) = o.z - o.h.uv_distorted - applyH<kCam>(o, dx);
    }
    Eigen::VectorXd next = state.x();
    if (!correct(nu, &next)) return false;
    const double step = (next.head<kPose>() - iterate->head<kPose>()).lpNorm<Eigen::Infinity>();
    *iterate = std::move(next);
    if (step < tolerance) break;
  }
  return true;
}

// x = iterate and P -= W W^T, the observations then predicted there (their residuals are the
// update's).
void finishIteratedUpdate(EkfState& state, const Eigen::MatrixXd& W, Eigen::VectorXd iterate,
                          std::vector<PointObservation>* observations, const Relinearise& relinearise) {
  state.x() = std::move(iterate);
  downdate(state, W);
  relinearise(state.x(), observations);  // h where it can be predicted
}

// Known points alone (the board's corners): H = [H_c 0] with H_c over (r, q), and R = s^2 I (with a
// shared shift, R = s^2 I + J C J^T: H_c and nu are whitened by s R^-1/2, and all below holds). With
// G^T G = H_c^T H_c (G 7 x 7, from the eigen-decomposition; rank 6, q's length is unobserved) the
// push-through identity gives H_c^T S^-1 H_c = G^T N^-1 G and K nu = P_c G^T N^-1 G^-T H_c^T nu,
// with N = G P_cc G^T + s^2 I (P_c: P's (r, q) columns, P_cc their 7 x 7 top). N and S have the
// same eigenvalues but for some equal to s^2, so S is positive definite when N is. No 2m x 2m
// matrix is formed or factored, and K S K^T = W W^T with W = P_c G^T L^-T (N = L L^T): rank 7.
// (Seen at their rows' times, over (r, q, v, w), the 13 x 13 gain strays from the dense formula
// by up to 500 times the batch update's: v and w barely move h, and N's eigenvalues spread.)
bool iteratedCameraUpdate(EkfState& state, std::vector<PointObservation>* observations, const PointNoise& noise,
                          const Relinearise& relinearise, int max_iterations, double tolerance) {
  using Mat77 = Eigen::Matrix<double, kPose, kPose>;
  using Vec7 = Eigen::Matrix<double, kPose, 1>;
  const auto P_c = state.P().leftCols<kPose>();  // P is not written before the downdate
  const Mat77 P_cc = P_c.topRows<kPose>();
  const double noise_var = noise.sigma * noise.sigma;
  // The shared shift by Woodbury: sigma^2 R^-1 = I - J M J^T, M = C (sigma^2 I + m C)^-1 (C the
  // shift's covariance; C and sigma^2 I + m C commute, so M is symmetric and needs no C^-1).
  const double m = static_cast<double>(observations->size());
  const Mat2 M = noise.shared * (noise_var * Mat2::Identity() + m * noise.shared).inverse();
  const bool shared = !noise.shared.isZero(0);
  Mat77 G;
  Eigen::LLT<Mat77> N;
  const auto correct = [&](const Eigen::VectorXd& nu, Eigen::VectorXd* x) {  // false: S not positive definite
    Mat77 HtH = Mat77::Zero();
    Vec7 Ht_nu = Vec7::Zero();
    Eigen::Matrix<double, 2, kPose> H_sum = Eigen::Matrix<double, 2, kPose>::Zero();
    Vec2 nu_sum = Vec2::Zero();
    for (size_t k = 0; k < observations->size(); ++k) {
      const Eigen::Matrix<double, 2, kPose> H = cameraJacobian<kPose>((*observations)[k].h);
      HtH.noalias() += H.transpose() * H;
      Ht_nu.noalias() += H.transpose() * nu.segment<2>(2 * static_cast<long>(k));
      H_sum += H;
      nu_sum += nu.segment<2>(2 * static_cast<long>(k));
    }
    if (shared) {  // H^T (I - J M J^T) H and H^T (I - J M J^T) nu: sigma^2 times the whitened ones
      HtH.noalias() -= H_sum.transpose() * M * H_sum;
      Ht_nu.noalias() -= H_sum.transpose() * (M * nu_sum);
    }
    const Eigen::SelfAdjointEigenSolver<Mat77> eigen(HtH);
    const Vec7 lambda = eigen.eigenvalues().cwiseMax(0.0);
    G = lambda.cwiseSqrt().asDiagonal() * eigen.eigenvectors().transpose();
    N.compute(G * P_cc * G.transpose() + noise_var * Mat77::Identity());
    if (N.info() != Eigen::Success) return false;
    // G^-T H_c^T nu: H_c^T nu lies in G^T's range, so the directions H_c does not see are left out.
    Vec7 c = eigen.eigenvectors().transpose() * Ht_nu;
    for (int i = 0; i < kPose; ++i) c(i) = lambda(i) > 1e-12 * lambda.maxCoeff() ? c(i) / std::sqrt(lambda(i)) : 0.0;
    x->noalias() += P_c * (G.transpose() * N.solve(c));
    return true;
  };
  Eigen::VectorXd iterate;
  if (!gaussNewton<kPose>(state, observations, relinearise, max_iterations, tolerance, correct, &iterate)) return false;
  Eigen::MatrixXd W = P_c * G.transpose();  // G and N are the last iteration's
  N.matrixU().solveInPlace<Eigen::OnTheRight>(W);
  finishIteratedUpdate(state, W, std::move(iterate), observations, relinearise);
  return true;
}

}  // namespace

bool iteratedUpdate(EkfState& state, std::vector<PointObservation>* observations, const PointNoise& noise,
                    const Relinearise& relinearise, int max_iterations, double tolerance) {
  if (observations->empty()) return true;
  const bool moving = anyRowTimed(*observations);
  if (knownPointsOnly(*observations) && !moving)
    return iteratedCameraUpdate(state, observations, noise, relinearise, max_iterations, tolerance);
  Eigen::MatrixXd W, S;
  Eigen::LLT<Eigen::MatrixXd> llt;
  const long m = static_cast<long>(observations->size());
  const bool shared = !noise.shared.isZero(0);
  const auto correct = [&](const Eigen::VectorXd& nu, Eigen::VectorXd* x) {
    gainInnovation(state.P(), *observations, noise.sigma, &W, &S, nullptr);
    for (long i = 0; shared && i < m; ++i)  // + J C J^T, the lower triangle (all that is read)
      for (long j = 0; j <= i; ++j) S.block<2, 2>(2 * i, 2 * j) += noise.shared;
    llt.compute(S.selfadjointView<Eigen::Lower>());
    if (llt.info() != Eigen::Success) return false;
    x->noalias() += W * llt.solve(nu);
    return true;
  };
  Eigen::VectorXd iterate;
  if (!(moving ? gaussNewton<kMoving>(state, observations, relinearise, max_iterations, tolerance, correct, &iterate)
               : gaussNewton<kPose>(state, observations, relinearise, max_iterations, tolerance, correct, &iterate)))
    return false;
  llt.matrixU().solveInPlace<Eigen::OnTheRight>(W);  // P -= K_i S_i K_i^T = W S^-1 W^T, as in batchUpdate
  finishIteratedUpdate(state, W, std::move(iterate), observations, relinearise);
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
