#pragma once
// A filter's honesty against ground truth (SPEC section 4 `nees`): the normalised estimation error
// squared of the pose, e^T P^-1 e over its 6 dof (position, world-frame rotation vector), averaged
// over the run, with the 95 % bounds of that average for a consistent filter (Bar-Shalom, Li and
// Kirubarajan 2001, 5.4.2: N times the average is chi-square with 6N dof).
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/tracker.h"
#include "core/trajectory.h"
#include "eval/metrics/align_umeyama.h"

namespace slamcmp {

struct CovariantPose {
  double timestamp = 0;
  SE3 T_world_camera;
  PoseCovariance covariance;
};

// One scored pose's NEES, at the estimate's timestamp.
struct TimedNees {
  double timestamp = 0;
  double nees = 0;
};

struct NeesResult {
  double mean = 0;
  int dof = 6;
  double lower = 0, upper = 0;  // 95 % bounds of the mean for a consistent filter
  std::vector<TimedNees> per_frame;  // the poses scored, in the estimate's order (nees.csv)
  int frames() const { return static_cast<int>(per_frame.size()); }
};

// Poses associated with the ground truth by timestamp (within max_diff seconds); poses whose
// covariance is not positive definite are skipped. Nothing when no pose can be scored.
// T_gt_estimate: the alignment of a scale-free run (run_errors.h), applied to each pose and its
// covariance (position block by s R, rotation block by R) before scoring.
// gauge_at_first: the run's world is its first camera, exactly (a board-free filter's gauge):
// T_gt_estimate's rotation and translation are replaced by those putting the first associated
// pose on its ground truth, its scale kept. A fit over the whole run moves that camera off its
// truth by the fit's residual, which covariances grown from that camera cannot explain (tv1
// board-free: 141 with the fit, 0.96 with the gauge). That first pose is on its truth by
// construction and is not scored.
std::optional<NeesResult> poseNees(const Trajectory& groundtruth, const std::vector<CovariantPose>& estimate,
                                   double max_diff, const Similarity3& T_gt_estimate = Similarity3(),
                                   bool gauge_at_first = false);

// The chi-square quantile (Wilson and Hilferty's approximation, within 0.1 % from 30 dof up).
double chiSquareQuantile(double probability, double dof);

nlohmann::json neesToJson(const NeesResult& nees);

// nees.csv: `timestamp,nees`, a row a scored pose (what compare's Monte Carlo test reads back). The
// reader throws InputError naming the file, line and field of a value that is not a finite number
// (or a NEES below zero).
void writeNeesCsv(const std::string& path, const std::vector<TimedNees>& rows);
std::vector<TimedNees> readNeesCsv(const std::string& path);

}  // namespace slamcmp
