#pragma once
// The EKF update from the matched points of a frame, in one batch.
#include <functional>
#include <vector>

#include "ekf/ekf_state.h"
#include "ekf/measurement_model.h"

namespace slamcmp {

// A point whose world position is known exactly and is not in the state (a board corner): its
// measurement depends on the camera only.
constexpr int kKnownPoint = -1;

struct PointObservation {
  int offset = 0;          // state offset of the feature's block (h.H_y's columns wide), or kKnownPoint
  Vec2 z = Vec2::Zero();   // measured pixel (distorted)
  PointMeasurement h;      // prediction and Jacobians at the prior state
};

// One point's innovation covariance H P H^T + pixel_sigma^2 I. H is non-zero only over the
// camera's (r, q) (and v, w when h is row_timed: a rolling shutter's), which lead the state, and
// the feature's y, so only those (7 or 13, + 3 or 6)^2 entries of P are read: O(1) whatever the
// map size.
Mat2 pointInnovationCovariance(const EkfState& state, const PointMeasurement& h, int offset, double pixel_sigma);

// The joint innovation covariance of the stacked predictions (2m x 2m, observation i at rows 2i,
// 2i+1), from the rows and columns of (r, q) (and v, w if one is row_timed) and the m points only:
// O(m^2).
Eigen::MatrixXd innovationCovariance(const EkfState& state, const std::vector<PointObservation>& observations,
                                     double pixel_sigma);

// The Kalman update from W = P H^T (n x m), S = H P H^T + R (its lower triangle is read) and
// nu = z - h: x += W S^-1 nu, P -= W S^-1 W^T (as below), q renormalised. Returns false, leaving
// the state untouched, when S is not positive definite.
bool kalmanUpdate(EkfState& state, Eigen::MatrixXd W, const Eigen::MatrixXd& S, Eigen::VectorXd nu);

// K = P H^T S^-1, x += K (z - h), P -= K S K^T, then q renormalised with its Jacobian applied to P.
// With S = L L^T and W = P H^T L^-T: x += W L^-1 (z - h) and P -= W W^T, a symmetric rank-2m
// update of P's lower triangle mirrored to the upper (O(n^2 m), half the flops of K (P H^T)^T,
// and P stays exactly symmetric; the Joseph form would cost O(n^3)).
// Returns false, leaving the state untouched, when S is not positive definite.
bool batchUpdate(EkfState& state, const std::vector<PointObservation>& observations, double pixel_sigma);

// The observations' pixel noise: independent per coordinate (sigma), and a shift of the whole image
// that every observation of the frame shares (`shared`, covariance in pixels^2): a motion-blurred
// frame shows each point where it was on average over the exposure, off its place at mid-exposure
// by the same amount over the image when the camera accelerates (hybrid/exposure_shift.h).
struct PointNoise {
  PointNoise(double sigma) : sigma(sigma) {}  // NOLINT: a plain sigma is independent noise
  PointNoise(double sigma, const Mat2& shared) : sigma(sigma), shared(shared) {}
  double sigma;
  Mat2 shared = Mat2::Zero();
};

// Re-predicts every observation's h (prediction and Jacobians) at the camera of the state vector x;
// false when one cannot be predicted there (behind the camera).
using Relinearise = std::function<bool(const Eigen::VectorXd& x, std::vector<PointObservation>* observations)>;

// The iterated EKF update (Bell and Cathey 1993: Gauss-Newton on the prior and the measurements):
// x_{i+1} = x_0 + K_i (z - h(x_i) - H_i (x_0 - x_i)), with H_i and K_i = P H_i^T S_i^-1 at x_i,
// until the camera moves by less than `tolerance` (metres, quaternion units) or after
// `max_iterations` (below 1 is 1); P from the last K_i and H_i. One iteration is batchUpdate. For
// known points alone at the frame's time, whose H touches only (r, q), the gain is formed in 7 x 7
// (no 2m x 2m S) and P's update has rank at most 7 where batchUpdate's has 2m: the same x and P up
// to rounding; row-timed ones (over r, q, v, w) take batchUpdate's form.
// It matters where the prior is far from the measurements compared with their noise (a board
// found again after a drift: one linearisation there lands centimetres off). `observations`
// leave with h at the updated state (where it can be predicted), so z - h are the update's
// residuals. Returns false, leaving the state untouched, when S is not positive definite or an
// observation cannot be predicted at an iterate.
// The noise's shared shift enters R = sigma^2 I + J shared J^T (J stacks m 2 x 2 identities).
bool iteratedUpdate(EkfState& state, std::vector<PointObservation>* observations, const PointNoise& noise,
                    const Relinearise& relinearise, int max_iterations = 5, double tolerance = 1e-7);

// The camera's orientation measured whole (R_world_camera, e.g. by two-view geometry) with std
// sigma_rad about each axis: the residual is 2 vec(q_m^-1 q), to first order the rotation vector
// of the camera's error in its own frame, linear in q (H = 2 [0 I] L(q_m^-1), L the left
// quaternion product).
// Returns false, leaving the state untouched, when S is not positive definite.
bool orientationUpdate(EkfState& state, const Mat3& R_world_camera, double sigma_rad);

// The state correction K (z - h) of a few observations, without touching P (1-point RANSAC's
// hypotheses, Civera et al. 2010): O(n m). Zero when S is not positive definite.
Eigen::VectorXd stateCorrection(const EkfState& state, const std::vector<PointObservation>& observations,
                                double pixel_sigma);

}  // namespace slamcmp
