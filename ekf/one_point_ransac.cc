#include "ekf/one_point_ransac.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <Eigen/Eigenvalues>
#include <Eigen/LU>

#include "core/statistics.h"

namespace slamcmp {

std::vector<size_t> lowInnovationInliers(const EkfState& state, const std::vector<PointObservation>& observations,
                                         const ObservationPredictor& predict, const OnePointRansacOptions& options,
                                         double pixel_sigma, std::mt19937& rng) {
  const size_t m = observations.size();
  std::vector<size_t> best;
  if (m == 0) return best;
  // The prior's turn std (a small rotation of angle a moves the quaternion by a / 2): beyond
  // max_turn_sigma a hypothesis draws two matches, which fix a roll that one leaves free.
  const double turn_sigma = 2 * largestStd(state.P().block<4, 4>(EkfState::kQ, EkfState::kQ));
  const size_t sample = turn_sigma > options.max_turn_sigma && m >= 2 ? 2 : 1;
  std::vector<size_t> order(m);
  std::iota(order.begin(), order.end(), 0);
  double hypotheses = options.max_hypotheses;
  for (int i = 0; i < hypotheses; ++i) {
    // The hypothesis: the state after the drawn matches alone (q renormalised), every match predicted from it.
    std::vector<PointObservation> drawn;
    for (size_t j = 0; j < sample; ++j) {
      std::swap(order[j], order[std::uniform_int_distribution<size_t>(j, m - 1)(rng)]);
      drawn.push_back(observations[order[j]]);
    }
    Eigen::VectorXd x = state.x() + stateCorrection(state, drawn, pixel_sigma);
    x.segment<4>(EkfState::kQ).normalize();
    std::vector<size_t> support;
    for (size_t k = 0; k < m; ++k) {
      PointMeasurement h;
      if (predict(x, k, &h) && (observations[k].z - h.uv_distorted).norm() < options.inlier_pixels)
        support.push_back(k);
    }
    if (support.size() <= best.size()) continue;
    best = std::move(support);
    // As many hypotheses as give an all-inlier draw with `probability`.
    hypotheses = std::min<double>(options.max_hypotheses, ransacTrials(static_cast<double>(best.size()) / m,
                                                                       static_cast<int>(sample), options.probability));
  }
  return best;
}

std::vector<size_t> onePointRansacUpdate(EkfState& state, const std::vector<PointObservation>& observations,
                                         const ObservationPredictor& predict, const OnePointRansacOptions& options,
                                         double pixel_sigma, std::mt19937& rng) {
  std::vector<size_t> used = lowInnovationInliers(state, observations, predict, options, pixel_sigma, rng);
  std::vector<PointObservation> low;
  for (size_t k : used) low.push_back(observations[k]);
  if (low.empty() || !batchUpdate(state, low, pixel_sigma)) return {};
  // High-innovation inliers: the remaining matches against the updated prediction and its covariance.
  const double gate = chiSquaredQuantile(2, options.rescue_gate);
  std::vector<PointObservation> rescued;
  std::vector<size_t> rescued_index;
  for (size_t k = 0; k < observations.size(); ++k) {
    if (std::binary_search(used.begin(), used.end(), k)) continue;
    PointObservation o = observations[k];
    if (!predict(state.x(), k, &o.h)) continue;
    const Vec2 nu = o.z - o.h.uv_distorted;
    if (nu.dot(pointInnovationCovariance(state, o.h, o.offset, pixel_sigma).inverse() * nu) > gate) continue;
    rescued.push_back(o);
    rescued_index.push_back(k);
  }
  if (!rescued.empty() && batchUpdate(state, rescued, pixel_sigma)) {
    used.insert(used.end(), rescued_index.begin(), rescued_index.end());
    std::sort(used.begin(), used.end());
  }
  return used;
}

}  // namespace slamcmp
