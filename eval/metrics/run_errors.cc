#include "eval/metrics/run_errors.h"

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
  r.rpe_trans_rmse = e.rpe_trans_stats.rmse;
  r.rpe_rot_rmse_deg = e.rpe_rot_deg_stats.rmse;
  r.drift = e.drift;
  r.json = evaluationToJson(e, options);
  return r;
}

}  // namespace slamcmp
