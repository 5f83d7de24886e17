#pragma once
// Pairs the poses of two trajectories by timestamp, exactly as evo's sync.associate_trajectories
// (nearest_time, no offset) does, so that the pairs and hence every metric agree with evo_ape.
#include <cstddef>
#include <vector>

#include "core/trajectory.h"

namespace slamcmp {

// groundtruth[k] is paired with estimate[k].
struct PosePairs {
  std::vector<size_t> groundtruth;
  std::vector<size_t> estimate;
  size_t size() const { return estimate.size(); }
};

// For each pose of the trajectory with fewer poses (the estimate when both have as many), the
// pose of the other nearest in time (the earlier one on a tie), kept if |dt| <= max_diff seconds.
// Pairs follow the shorter trajectory's order; a pose of the longer one may serve twice.
// Repeated timestamps are allowed (published ground truth has some; the first of equally near
// poses wins). Throws InputError when a timestamp goes back in time, or when no pair is found: the
// message gives both time ranges and the usual causes (ns against s timestamps, a too small
// --max-diff).
PosePairs associateByTime(const Trajectory& groundtruth, const Trajectory& estimate,
                          double max_diff);

}  // namespace slamcmp
