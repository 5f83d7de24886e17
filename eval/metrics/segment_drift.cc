#include "eval/metrics/segment_drift.h"

#include <cmath>
#include <sstream>

namespace slamcmp {

namespace {

constexpr int kStepSize = 10;  // the devkit's step_size: a segment starts at every 10th pose
// The devkit's lengths on paths of KITTI's size: its shorter drives (03: 561 m, 04: 394 m) get
// them too, and the lengths no segment fits add nothing, as in the devkit. Below 300 m a path
// would get its 100 m segments from a few starts only (EuRoC's MH_03, 131 m: from its first 31 m),
// so tenths of the path, as for a room.
constexpr double kKittiPathM = 300.0;
bool kittiLengths(double path_m) { return path_m > kKittiPathM; }

// The devkit's rotationError: acos(max(min(0.5 (trace - 1), 1), -1)).
double rotationErrorRad(const Mat3& R) {
  const double d = 0.5 * (R.trace() - 1.0);
  return std::acos(std::max(std::min(d, 1.0), -1.0));
}

}  // namespace

std::vector<double> driftSegmentLengths(double path_m) {
  std::vector<double> lengths;
  const bool kitti = kittiLengths(path_m);
  for (int k = 1; k <= 8; ++k) lengths.push_back(kitti ? 100.0 * k : 0.1 * k * path_m);
  return lengths;
}

double pathLength(const std::vector<SE3>& T) {
  double length = 0;
  for (size_t i = 1; i < T.size(); ++i) length += (T[i].t() - T[i - 1].t()).norm();
  return length;
}

std::optional<SegmentDrift> segmentDrift(const std::vector<SE3>& T_world_gt, const std::vector<SE3>& T_world_est,
                                         double path_m, std::string* why_none) {
  const auto none = [why_none](const std::string& why) {
    if (why_none) *why_none = why;
    return std::nullopt;
  };
  if (!(path_m > 0)) return none("the ground truth does not move");
  if (T_world_gt.size() < 2) return none("fewer than 2 matched poses");
  // The devkit's trajectoryDistances: the path travelled up to each pose.
  std::vector<double> dist(T_world_gt.size(), 0.0);
  for (size_t i = 1; i < dist.size(); ++i) dist[i] = dist[i - 1] + (T_world_gt[i].t() - T_world_gt[i - 1].t()).norm();
  // A segment's error is divided by its nominal length, though it ends at the first pose beyond
  // it: poses further apart on average than even the longest segment (2 poses 6 mm apart against
  // tenths of 0.6 to 4.8 mm) make every segment the same one motion, many times its length, and
  // its drift that many times too. The devkit's KITTI poses are 1 m apart against 100..800 m.
  const double longest = driftSegmentLengths(path_m).back();
  const double spacing = dist.back() / static_cast<double>(dist.size() - 1);
  if (spacing > longest) {
    std::ostringstream why;
    why << "the " << dist.size() << " matched poses are " << spacing << " m apart on average, more than the "
        << "longest segment (" << longest << " m): too few to measure drift over segments";
    return none(why.str());
  }

  SegmentDrift out;
  out.path_m = path_m;
  out.kitti_lengths = kittiLengths(path_m);
  double trans_sum = 0, rot_sum = 0;
  for (const double length : driftSegmentLengths(path_m)) {
    DriftAtLength at;
    at.length_m = length;
    for (size_t first = 0; first < dist.size(); first += kStepSize) {
      // lastFrameFromSegmentLength: the first pose strictly further than `length` along the path.
      size_t last = first;
      while (last < dist.size() && !(dist[last] > dist[first] + length)) ++last;
      if (last == dist.size()) continue;
      const SE3 delta_gt = T_world_gt[first].inverse() * T_world_gt[last];
      const SE3 delta_est = T_world_est[first].inverse() * T_world_est[last];
      const SE3 error = delta_est.inverse() * delta_gt;
      const double t_err = error.t().norm() / length;
      const double r_err = rotationErrorRad(error.R()) / length;
      at.trans_percent += t_err;
      at.rot_deg_per_m += r_err;
      trans_sum += t_err;
      rot_sum += r_err;
      ++at.segments;
    }
    if (at.segments == 0) continue;
    at.trans_percent *= 100.0 / at.segments;
    at.rot_deg_per_m *= (180.0 / M_PI) / at.segments;
    out.segments += at.segments;
    out.lengths.push_back(at);
  }
  if (out.segments == 0) return none("no segment fits between the matched poses");
  out.trans_percent = 100.0 * trans_sum / out.segments;
  out.rot_deg_per_m = (180.0 / M_PI) * rot_sum / out.segments;
  return out;
}

nlohmann::json driftToJson(const SegmentDrift& d) {
  nlohmann::json lengths = nlohmann::json::array(), per_length = nlohmann::json::array();
  for (const DriftAtLength& at : d.lengths) {
    lengths.push_back(at.length_m);
    per_length.push_back({{"length_m", at.length_m},
                          {"segments", at.segments},
                          {"trans_percent", at.trans_percent},
                          {"rot_deg_per_m", at.rot_deg_per_m}});
  }
  return {{"segments_m", lengths},
          {"trans_percent", d.trans_percent},
          {"rot_deg_per_m", d.rot_deg_per_m},
          {"segments", d.segments},
          {"path_m", d.path_m},
          {"lengths_from", d.kitti_lengths ? "kitti 100..800 m" : "tenths of the path"},
          {"per_length", per_length}};
}

}  // namespace slamcmp
