#include "ekf/adaptive_motion_noise.h"

#include <algorithm>
#include <cmath>

namespace slamcmp {

AdaptiveMotionNoise::AdaptiveMotionNoise(const MotionModelOptions& options)
    : set_(options),
      current_(options),
      mean_a2_(options.sigma_a * options.sigma_a),
      mean_alpha2_(options.sigma_alpha * options.sigma_alpha) {}

const MotionModelOptions& AdaptiveMotionNoise::next(const EkfState& posterior, double dt) {
  const double interval = last_dt_;  // the interval that ended at `posterior`
  last_dt_ = dt;
  const AdaptiveMotionOptions& adaptive = set_.adaptive;
  if (!adaptive.enabled) return current_;
  const Eigen::MatrixXd& P = posterior.P();
  const double trace_v = P.block<3, 3>(EkfState::kV, EkfState::kV).trace();
  const double trace_w = P.block<3, 3>(EkfState::kW, EkfState::kW).trace();
  if (has_last_ && std::isfinite(trace_v) && std::isfinite(trace_w)) {
    // Per-axis impulse variance over dt, as a sigma^2 at the reference rate (motion_model.h:
    // var = sigma^2 dt / reference_rate).
    const double to_sigma2 = set_.reference_rate / interval / 3;
    const double a2 = ((posterior.v() - last_v_).squaredNorm() + trace_v - last_trace_v_) * to_sigma2;
    const double alpha2 = ((posterior.w() - last_w_).squaredNorm() + trace_w - last_trace_w_) * to_sigma2;
    const double weight = 1 - std::exp(-interval / adaptive.time_constant);
    // The means stay between the floor and the set value, so a run of small samples does not
    // leave them far below where a sudden turn must bring them back.
    const auto average = [weight](double& mean2, double sample2, double floor, double ceiling) {
      if (std::isfinite(sample2)) mean2 += weight * (sample2 - mean2);
      mean2 = std::clamp(mean2, floor * floor, ceiling * ceiling);  // floor <= ceiling: checked
      return std::sqrt(mean2);
    };
    current_.sigma_a = average(mean_a2_, a2, adaptive.min_sigma_a, set_.sigma_a);
    current_.sigma_alpha = average(mean_alpha2_, alpha2, adaptive.min_sigma_alpha, set_.sigma_alpha);
  }
  has_last_ = true;
  last_v_ = posterior.v();
  last_w_ = posterior.w();
  last_trace_v_ = trace_v;
  last_trace_w_ = trace_w;
  return current_;
}

}  // namespace slamcmp
