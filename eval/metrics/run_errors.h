#pragma once
// A run's error against ground truth as run's summary.json and compare's tables report it: no
// alignment (the world frame is the board frame for every back-end started from the board), or
// Sim(3) for a scale-free run (`--init none`: its world frame is its first camera's, its unit
// arbitrary); RPE over 1 frame, timestamps associated within 10 ms.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/trajectory.h"
#include "eval/metrics/align_umeyama.h"
#include "eval/metrics/segment_drift.h"

namespace slamcmp {

struct RunErrors {
  double ate_trans_rmse = 0;    // metres
  double ate_rot_rmse_deg = 0;  // degrees
  std::string ate_rot_warning;  // why the rotation error is not determined (positions on a line), or ""
  double rpe_trans_rmse = 0;    // metres, per frame
  double rpe_rot_rmse_deg = 0;  // degrees, per frame
  std::string align = "none";   // none | sim3
  Similarity3 T_gt_estimate;    // the alignment applied (its scale: ground-truth metres per estimate unit)
  std::optional<SegmentDrift> drift;  // KITTI devkit drift, when a segment fits
  nlohmann::json json;          // the `slamcmp eval --json` object
};

// Nothing for an estimate of fewer than two poses; throws InputError when no pose can be associated.
// align: "none" or "sim3" (summary.json's `alignment`).
std::optional<RunErrors> evaluateRun(const Trajectory& groundtruth, const Trajectory& estimate,
                                     const std::string& align = "none");

// For a run started from the board, which is in the board's world as its ground truth must be:
// "" unless a similarity fits it far better than none (5 times), with a scale or a turn (5 % or 5
// degrees), and to within a tenth of how far the true camera moved; then the fit and the likely
// cause (target.yaml's square size; its inner corner counts swapped turn the world by 90 degrees).
std::string boardWorldMismatch(const Trajectory& groundtruth, const Trajectory& estimate, double ate_rmse_m);

}  // namespace slamcmp
