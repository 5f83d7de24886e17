#include "eval/metrics/trajectory_metrics.h"

#include <cmath>
#include <sstream>
#include <string>

#include "core/error.h"

namespace slamcmp {

namespace {

constexpr double kDegreesPerRadian = 180.0 / M_PI;

Vec3 axisRms(const std::vector<Vec3>& v) {
  Vec3 sum = Vec3::Zero();
  for (const Vec3& x : v) sum += x.cwiseProduct(x);
  return (sum / static_cast<double>(v.size())).cwiseSqrt();
}

nlohmann::json statisticsToJson(const Statistics& s) {
  return {{"rmse", s.rmse}, {"mean", s.mean}, {"median", s.median},
          {"std", s.std},   {"min", s.min},   {"max", s.max}};
}

nlohmann::json axesToJson(const Vec3& v) { return {{"x", v.x()}, {"y", v.y()}, {"z", v.z()}}; }

// The alignment's turn about the matched positions' main axis is fixed by how far they spread
// across it: on a line (across under a tenth of along) and across under ten times the ATE, the
// turn is uncertain by more than a tenth of a radian, and a rotation error of tens of degrees may
// be the fit's alone (a Sim(3) of 40 frames along 0.1 m with 3 mm across: 99 degrees where the
// positions were 1-6 mm off). TUM's freiburg1_xyz (0.13 m along, 0.10 across) is no line.
std::string lineAlignmentWarning(const std::vector<Vec3>& p_gt, double ate_rmse_m) {
  const Vec3 spread = principalSpread(p_gt);  // ascending
  constexpr double kMinAcrossOverAte = 10, kMaxLineAcrossOverAlong = 0.1;
  if (spread[1] >= kMaxLineAcrossOverAlong * spread[2] || spread[1] >= kMinAcrossOverAte * ate_rmse_m) return "";
  std::ostringstream why;
  why.precision(3);
  why << "the matched positions lie nearly on a line (" << spread[2] << " m RMS along it, " << spread[1]
      << " m across, the ATE " << ate_rmse_m << " m): the alignment's turn about it, and so the rotation error, "
      << "is not determined";
  return why.str();
}

}  // namespace

void EvalOptions::check() const {
  if (align != "none" && align != "se3" && align != "sim3" && align != "origin")
    throw InputError("--align", "must be none, se3, sim3 or origin, got '" + align + "'");
  if (!(max_diff >= 0.0) || !std::isfinite(max_diff))
    throw InputError("--max-diff", "must be a finite number of seconds >= 0");
  if (!std::isfinite(t_offset)) throw InputError("--t-offset", "must be a finite number of seconds");
  if (delta < 1)
    throw InputError("--delta", "must be at least 1 frame, got " + std::to_string(delta));
}

TrajectoryEvaluation evaluateTrajectory(const Trajectory& groundtruth, const Trajectory& estimate,
                                        const EvalOptions& options) {
  options.check();
  TrajectoryEvaluation out;
  out.align = options.align;
  out.rpe_delta = options.delta;
  out.rpe_all_pairs = options.all_pairs;
  // As evo's associate_trajectories(offset_2) and TUM's associate.py --offset: a constant clock
  // offset of the estimate (a camera stamped on arrival, not exposure).
  try {
    out.pairs = associateByTime(groundtruth, estimate, options.max_diff, options.t_offset);
  } catch (const InputError& e) {  // the times it quotes are the shifted ones: say so
    if (options.t_offset == 0.0) throw;
    std::ostringstream offset;
    offset << options.t_offset;
    throw InputError("", std::string(e.what()) + " (the estimate's times after --t-offset " + offset.str() + " s)");
  }
  const size_t n = out.pairs.size();

  std::vector<SE3> T_world_gt(n), T_world_est(n);
  for (size_t k = 0; k < n; ++k) {
    T_world_gt[k] = groundtruth[out.pairs.groundtruth[k]].T_world_camera;
    T_world_est[k] = estimate[out.pairs.estimate[k]].T_world_camera;
  }

  std::vector<Vec3> p_gt_aligned;  // the true positions an se3 or sim3 alignment was fitted to
  if (options.align == "origin") {
    // evo's PosePath3D.align_origin: T_gt[0] T_est[0]^-1 applied on the left of every pose, so
    // that the errors are those of each pose relative to the first (a run's own world frame).
    const SE3 T_gt_estimate = T_world_gt.front() * T_world_est.front().inverse();
    out.T_gt_estimate.R = T_gt_estimate.R();
    out.T_gt_estimate.t = T_gt_estimate.t();
  } else if (options.align != "none") {
    std::vector<Vec3> p_est(n), p_gt(n);
    for (size_t k = 0; k < n; ++k) {
      p_est[k] = T_world_est[k].t();
      p_gt[k] = T_world_gt[k].t();
    }
    out.T_gt_estimate = alignUmeyama(p_est, p_gt, options.align == "sim3");
    p_gt_aligned = std::move(p_gt);
  }
  // As evo's PosePath3D.align: scale the positions, then apply the rigid part to every pose.
  if (options.align != "none")
    for (SE3& T : T_world_est) T = SE3(out.T_gt_estimate.R * T.R(), out.T_gt_estimate * T.t());

  out.ate_trans.resize(n);
  out.ate_rot_deg.resize(n);
  std::vector<Vec3> ate_offsets(n);
  for (size_t k = 0; k < n; ++k) {
    ate_offsets[k] = T_world_est[k].t() - T_world_gt[k].t();
    out.ate_trans[k] = ate_offsets[k].norm();
    out.ate_rot_deg[k] =
        rotationAngle(T_world_gt[k].R().transpose() * T_world_est[k].R()) * kDegreesPerRadian;
  }
  out.ate_axis_rmse = axisRms(ate_offsets);
  out.ate_trans_stats = computeStatistics(out.ate_trans);
  out.ate_rot_deg_stats = computeStatistics(out.ate_rot_deg);
  if (!p_gt_aligned.empty()) out.ate_rot_warning = lineAlignmentWarning(p_gt_aligned, out.ate_trans_stats.rmse);

  // evo's filter_pairs_by_index: consecutive pairs, ids 0, delta, 2 delta, ... < n; or all pairs
  // (i, i + delta).
  const size_t delta = static_cast<size_t>(options.delta);
  const size_t step = options.all_pairs ? 1 : delta;
  if (n <= delta)
    throw InputError("", "RPE needs at least " + std::to_string(delta + 1) + " matched poses (pairs " +
                             std::to_string(delta) + " apart, --delta), got " + std::to_string(n));
  std::vector<Vec3> rpe_offsets;
  for (size_t i = 0; i + delta < n; i += step) {
    const size_t j = i + delta;
    const SE3 gt_motion = T_world_gt[i].inverse() * T_world_gt[j];
    const SE3 est_motion = T_world_est[i].inverse() * T_world_est[j];
    const SE3 E = gt_motion.inverse() * est_motion;
    rpe_offsets.push_back(E.t());
    out.rpe_trans.push_back(E.t().norm());
    out.rpe_rot_deg.push_back(rotationAngle(E.R()) * kDegreesPerRadian);
  }
  out.rpe_axis_rmse = axisRms(rpe_offsets);
  out.rpe_trans_stats = computeStatistics(out.rpe_trans);
  out.rpe_rot_deg_stats = computeStatistics(out.rpe_rot_deg);

  // Every ground-truth pose from the first matched one to the last: the path the run covered.
  std::vector<SE3> T_world_gt_covered;
  for (size_t i = out.pairs.groundtruth.front(); i <= out.pairs.groundtruth.back() && i < groundtruth.size(); ++i)
    T_world_gt_covered.push_back(groundtruth[i].T_world_camera);
  out.drift = segmentDrift(T_world_gt, T_world_est, pathLength(T_world_gt_covered), &out.no_drift);
  return out;
}

nlohmann::json evaluationToJson(const TrajectoryEvaluation& e, const EvalOptions& options) {
  nlohmann::json ate = {{"trans", statisticsToJson(e.ate_trans_stats)},
                        {"rot_deg", statisticsToJson(e.ate_rot_deg_stats)},
                        {"trans_axis_rmse", axesToJson(e.ate_axis_rmse)}};
  if (!e.ate_rot_warning.empty()) ate["rot_warning"] = e.ate_rot_warning;
  nlohmann::json rpe = {{"delta_frames", e.rpe_delta},
                        {"all_pairs", e.rpe_all_pairs},
                        {"pairs", e.rpe_trans.size()},
                        {"trans", statisticsToJson(e.rpe_trans_stats)},
                        {"rot_deg", statisticsToJson(e.rpe_rot_deg_stats)},
                        {"trans_axis_rmse", axesToJson(e.rpe_axis_rmse)}};
  nlohmann::json out = {{"matched", e.pairs.size()},    {"align", e.align}, {"scale", e.T_gt_estimate.scale},
                        {"max_diff", options.max_diff}, {"t_offset", options.t_offset},
                        {"ate", ate},                   {"rpe", rpe}};
  if (e.drift) out["drift"] = driftToJson(*e.drift);
  else out["no_drift"] = e.no_drift;
  return out;
}

}  // namespace slamcmp
