#pragma once
// A run's error against ground truth as run's summary.json and compare's tables report it: no
// alignment (the world frame is the board frame for every back-end), RPE over 1 frame, timestamps
// associated within 10 ms.
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "core/trajectory.h"
#include "eval/metrics/segment_drift.h"

namespace slamcmp {

struct RunErrors {
  double ate_trans_rmse = 0;    // metres
  double ate_rot_rmse_deg = 0;  // degrees
  double rpe_trans_rmse = 0;    // metres, per frame
  double rpe_rot_rmse_deg = 0;  // degrees, per frame
  std::string align;            // the alignment used (none | se3 | sim3)
  double scale = 1;             // its scale (1 unless sim3)
  std::optional<SegmentDrift> drift;  // KITTI devkit drift, when a segment fits
  nlohmann::json json;          // the `slamcmp eval --json` object
};

// Nothing for an estimate of fewer than two poses; throws InputError when no pose can be associated.
std::optional<RunErrors> evaluateRun(const Trajectory& groundtruth, const Trajectory& estimate);

}  // namespace slamcmp
