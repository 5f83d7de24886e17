#pragma once
// Trajectory error against ground truth (SPEC section 4): association, Umeyama alignment, absolute
// trajectory error (ATE) and relative pose error (RPE), with the statistics evo_ape / evo_rpe
// print, computed as evo computes them so that the figures agree to 1e-6 relative.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/statistics.h"
#include "core/trajectory.h"
#include "eval/metrics/align_umeyama.h"
#include "eval/metrics/associate.h"
#include "eval/metrics/segment_drift.h"

namespace slamcmp {

struct EvalOptions {
  // none | se3 | sim3: Umeyama alignment of the estimate onto the ground truth; origin: the
  // estimate moved so that its first matched pose is the ground truth's (evo's --align_origin)
  std::string align = "none";
  double max_diff = 0.01;      // s, largest time difference of an associated pose pair
  double t_offset = 0.0;       // s, added to the estimate's timestamps before association (evo's --t_offset)
  int delta = 1;               // RPE: frames (matched poses) between the two poses of a pair
  bool all_pairs = false;      // RPE over every pair (i, i + delta), not only i = 0, delta, 2 delta, ...

  template <class V>
  void visit(V& v) {
    v("align", align, "none | se3 | sim3 | origin: alignment of the estimate onto the ground truth");
    v("max_diff", max_diff, "s, largest time difference of an associated pose pair");
    v("t_offset", t_offset, "s, added to the estimate's timestamps before association");
    v("delta", delta, "RPE step in matched poses");
    v("all_pairs", all_pairs, "RPE over every pair delta apart, overlapping (evo_rpe --all_pairs)");
  }
  void check() const;  // throws InputError naming the option
};

struct TrajectoryEvaluation {
  PosePairs pairs;            // matched poses, in the order of the error arrays below
  std::string align;          // none | se3 | sim3 | origin
  Similarity3 T_gt_estimate;  // the alignment applied (identity for none; scale 1 unless sim3)
  // Per matched pose: |t_gt - t_est| (m) and the angle of R_gt^T R_est (degrees), after alignment.
  std::vector<double> ate_trans, ate_rot_deg;
  // Aligned (se3, sim3) on positions nearly on one line: its turn about the line, and so the
  // rotation error, is not determined; why, or "".
  std::string ate_rot_warning;
  Vec3 ate_axis_rmse = Vec3::Zero();  // m, rms of t_est - t_gt along x, y, z
  Statistics ate_trans_stats, ate_rot_deg_stats;
  // Per pair (i, i + delta), i = 0, delta, 2 delta, ... over the matched poses (every i with
  // all_pairs): translation norm (m) and angle (degrees) of E = (gt_i^-1 gt_j)^-1 (est_i^-1 est_j).
  int rpe_delta = 1;
  bool rpe_all_pairs = false;
  std::vector<double> rpe_trans, rpe_rot_deg;
  Vec3 rpe_axis_rmse = Vec3::Zero();  // m, rms of E's translation along x, y, z
  Statistics rpe_trans_stats, rpe_rot_deg_stats;
  // KITTI devkit drift over the matched poses (after alignment), its segment lengths set by the
  // ground truth's path over the time the matched poses span; nothing when no segment fits, and
  // then why in `no_drift`.
  std::optional<SegmentDrift> drift;
  std::string no_drift;
};

// Associates, aligns and measures. Throws InputError when no pose pairs are found, when an
// alignment has fewer than 3 pairs or degenerate positions, or when fewer than delta + 1 poses
// are matched (no RPE pair).
TrajectoryEvaluation evaluateTrajectory(const Trajectory& groundtruth, const Trajectory& estimate,
                                        const EvalOptions& options);

// SPEC section 4's object: matched, align, scale, ate {trans, rot_deg}, rpe {delta_frames, all_pairs, trans,
// rot_deg}, each statistic block rmse, mean, median, std, min, max; drift when it has segments
// (else no_drift, why not); plus max_diff, t_offset, ate.trans_axis_rmse, rpe.pairs and rpe.trans_axis_rmse.
nlohmann::json evaluationToJson(const TrajectoryEvaluation& evaluation, const EvalOptions& options);

}  // namespace slamcmp
