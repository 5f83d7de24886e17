#pragma once
// Pairs the poses of two trajectories by timestamp, exactly as evo's sync.associate_trajectories
// does (nearest time, its offset_2 included), so that the pairs and hence every metric agree with
// evo_ape.
#include <cstddef>
#include <vector>

#include "core/trajectory.h"

namespace slamcmp {

// The trajectory's timestamps; throws InputError naming `name` when one goes back in time.
std::vector<double> timestampsInOrder(const Trajectory& trajectory, const char* name);

// evo's argmin |times - t| (the first of equal minima) over times that do not decrease (not empty).
size_t nearestTimeIndex(const std::vector<double>& times, double t);

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
// poses wins). Throws InputError when a timestamp goes back in time; when fewer than half the
// shorter trajectory's poses pair up and the two files' times differ by a factor 1e3, 1e6 or 1e9
// (one in s, the other in ms, us or ns: the message gives the factor) or do not overlap at all
// (the message gives by how much); or when no pair is found (both time ranges, the usual causes).
// estimate_offset (s) is added to the estimate's clock; as evo does, it is added to the longer
// trajectory's times (subtracted from the ground truth's when that is longer), so that a pair
// exactly max_diff apart is kept or dropped as evo keeps or drops it. The messages quote the
// estimate's times with the offset added.
PosePairs associateByTime(const Trajectory& groundtruth, const Trajectory& estimate,
                          double max_diff, double estimate_offset = 0.0);

}  // namespace slamcmp
