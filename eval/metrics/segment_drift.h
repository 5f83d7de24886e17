#pragma once
// Drift over path segments as the KITTI odometry devkit measures it (evaluate_odometry.cpp,
// calcSequenceErrors): from every 10th pose, the first pose at least `length` further along the
// ground truth's path ends a segment; the error of the segment's relative motion, translation over
// the nominal length (%) and rotation angle over it (deg/m), averaged over every segment of every
// length.
//
// Segment lengths: the devkit's 100, 200, ..., 800 m on paths longer than 300 m (KITTI's drives;
// those no segment fits add nothing, as in the devkit), else a ladder of tenths of the path (0.1,
// 0.2, ..., 0.8 of its length), so that a room-scale run of a metre gets segments of 0.1..0.8 m
// from as many starts as a KITTI drive gets 100..800 m ones.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/geometry.h"

namespace slamcmp {

struct DriftAtLength {
  double length_m = 0;
  int segments = 0;
  double trans_percent = 0;  // mean over its segments of |t_err| / length * 100
  double rot_deg_per_m = 0;  // mean of angle(R_err) / length
};

struct SegmentDrift {
  double path_m = 0;            // the ground truth's path length the lengths come from
  bool kitti_lengths = false;   // 100..800 m (else tenths of the path)
  std::vector<DriftAtLength> lengths;  // those with at least one segment
  int segments = 0;
  double trans_percent = 0;  // mean over every segment (the devkit's average)
  double rot_deg_per_m = 0;
};

// The devkit's segment lengths for a path of `path_m` metres.
std::vector<double> driftSegmentLengths(double path_m);

// Path length of the positions in order (m).
double pathLength(const std::vector<SE3>& T_world_camera);

// T_world_gt[k] and T_world_est[k] are one matched pose pair, in time order. `path_m`: the whole
// ground truth's path length, which sets the segment lengths (so every method on a sequence gets
// the same ones, whatever it lost). Nothing when no segment fits, or when the matched poses are
// further apart on average than the longest segment is long (too few to measure any); then why in
// `why_none` when given.
std::optional<SegmentDrift> segmentDrift(const std::vector<SE3>& T_world_gt, const std::vector<SE3>& T_world_est,
                                         double path_m, std::string* why_none = nullptr);

// `drift` of eval --json: segments_m, trans_percent, rot_deg_per_m, path_m, lengths_from, per_length.
nlohmann::json driftToJson(const SegmentDrift& drift);

}  // namespace slamcmp
