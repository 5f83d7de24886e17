#pragma once
// 1-point RANSAC for the EKF update (Civera, Grasa, Davison and Montiel, "1-Point RANSAC for
// Extended Kalman Filtering", JFR 2010, Algorithm 1). The prior's covariance already constrains the
// state so much that one match fixes a hypothesis: a state-only EKF update with that match, the
// other matches predicted from it, those within a few pixels its support. The largest support
// (low-innovation inliers) updates the filter; matches that the updated, much tighter prediction
// then explains (high-innovation inliers) update it again.
#include <functional>
#include <random>
#include <vector>

#include "ekf/ekf_options.h"
#include "ekf/ekf_state.h"
#include "ekf/ekf_update.h"

namespace slamcmp {

// Observation k's prediction from the state vector x (false: not predictable from x).
using ObservationPredictor = std::function<bool(const Eigen::VectorXd& x, size_t k, PointMeasurement* h)>;

// The first half of Algorithm 1: the indices of the low-innovation inliers of `observations` (z set,
// h predicted at the state). The number of hypotheses adapts to the best support's inlier ratio
// w: log(1 - probability) / log(1 - w), at most max_hypotheses.
std::vector<size_t> lowInnovationInliers(const EkfState& state, const std::vector<PointObservation>& observations,
                                         const ObservationPredictor& predict, const OnePointRansacOptions& options,
                                         double pixel_sigma, std::mt19937& rng);

// The whole update: the low-innovation inliers in one batch, then the others re-predicted (with
// their covariance) and those inside the rescue gate (chi2, 2 dof) in a second batch. Returns the
// indices used, in increasing order; none (and the state untouched) when the first update fails.
std::vector<size_t> onePointRansacUpdate(EkfState& state, const std::vector<PointObservation>& observations,
                                         const ObservationPredictor& predict, const OnePointRansacOptions& options,
                                         double pixel_sigma, std::mt19937& rng);

}  // namespace slamcmp
