#include "eval/metrics/run_errors.h"

#include <cmath>

#include "core/error.h"
#include "core/format_string.h"
#include "eval/metrics/trajectory_metrics.h"

namespace slamcmp {

std::optional<RunErrors> evaluateRun(const Trajectory& groundtruth, const Trajectory& estimate,
                                     const std::string& align) {
  if (estimate.size() < 2) return std::nullopt;
  EvalOptions options;  // 10 ms, delta 1
  options.align = align;
  options.check();
  RunErrors r;
  const TrajectoryEvaluation e = evaluateTrajectory(groundtruth, estimate, options);
  r.align = e.align;
  r.T_gt_estimate = e.T_gt_estimate;
  r.ate_trans_rmse = e.ate_trans_stats.rmse;
  r.ate_rot_rmse_deg = e.ate_rot_deg_stats.rmse;
  r.ate_rot_warning = e.ate_rot_warning;
  r.rpe_trans_rmse = e.rpe_trans_stats.rmse;
  r.rpe_rot_rmse_deg = e.rpe_rot_deg_stats.rmse;
  r.drift = e.drift;
  r.json = evaluationToJson(e, options);
  return r;
}

std::string boardWorldMismatch(const Trajectory& groundtruth, const Trajectory& estimate, double ate_rmse_m) {
  constexpr double kMinAte = 0.01, kMinGain = 5, kMinScaleOff = 0.05, kMinTurnDeg = 5;
  if (!(ate_rmse_m > kMinAte)) return "";
  std::optional<RunErrors> fitted;
  try {
    fitted = evaluateRun(groundtruth, estimate, "sim3");
  } catch (const InputError&) {
    return "";
  }
  if (!fitted || !(fitted->ate_trans_rmse * kMinGain < ate_rmse_m)) return "";
  // A run gone astray also fits better once shrunk onto the truth's middle: the fit must leave
  // errors small against how far the true camera moved.
  constexpr double kMaxFitOverSpread = 0.1;
  std::vector<Vec3> p_gt;
  for (const StampedPose& pose : groundtruth) p_gt.push_back(pose.T_world_camera.t());
  if (!(fitted->ate_trans_rmse < kMaxFitOverSpread * principalSpread(p_gt).norm())) return "";
  const double scale = fitted->T_gt_estimate.scale;
  const double turn_deg = rotationAngle(fitted->T_gt_estimate.R) * 180 / M_PI;
  if (std::abs(scale - 1) < kMinScaleOff && turn_deg < kMinTurnDeg) return "";
  return formatString("the trajectory fits it after a scale of %.3f and a %.1f degree turn (ATE %.4g m without, "
                      "%.4g m with): is target.yaml's square_size or are its inner corner counts right?",
                      scale, turn_deg, ate_rmse_m, fitted->ate_trans_rmse);
}

}  // namespace slamcmp
