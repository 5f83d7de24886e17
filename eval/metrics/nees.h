#pragma once
// A filter's honesty against ground truth (SPEC section 4 `nees`): the normalised estimation error
// squared of the pose, e^T P^-1 e over its 6 dof (position, world-frame rotation vector), averaged
// over the run, with the 95 % bounds of that average for a consistent filter (Bar-Shalom, Li and
// Kirubarajan 2001, 5.4.2: N times the average is chi-square with 6N dof). Also its position and
// orientation parts, each over its own 3 x 3 block of the covariance (3 dof), as OpenVINS's
// ov_eval reports them: the 6-dof figure alone does not say which of the two is off.
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

// The position and orientation parts of one pose's NEES (3 dof each, their own covariance blocks).
struct NeesParts {
  double position = 0, orientation = 0;
};

// A mean over the scored poses with its 95 % bounds for a consistent filter.
struct NeesMean {
  double mean = 0;
  int dof = 6;
  double lower = 0, upper = 0;
};

// The whole pose's (6 dof) mean and bounds, and its parts'.
struct NeesResult : NeesMean {
  NeesMean position, orientation;  // the 3-dof parts' means and bounds
  std::vector<TimedNees> per_frame;  // the poses scored, in the estimate's order (nees.csv)
  std::vector<NeesParts> per_frame_parts;  // the same poses' parts
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

nlohmann::json neesToJson(const NeesResult& nees);

// nees.csv: `timestamp,nees,position,orientation`, a row a scored pose (the 6-dof NEES, what
// compare's Monte Carlo test reads back, and its 3-dof parts). The reader also takes the
// `timestamp,nees` files of earlier versions, and throws InputError naming the file, line and
// field of a value that is not a finite number (or a NEES below zero).
void writeNeesCsv(const std::string& path, const NeesResult& nees);
std::vector<TimedNees> readNeesCsv(const std::string& path);

}  // namespace slamcmp
