#include "eval/metrics/board_visibility.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "eval/metrics/associate.h"

namespace slamcmp {

namespace {

// The frames counted as settled lie this far from any frame without the whole board, and past
// the first kSettledFrom (the filters converging from the first view).
constexpr int kSettledMargin = 30;
constexpr int kSettledFrom = 10;

// Index of the time nearest t within max_diff, if any (times in order).
std::optional<size_t> nearestWithin(const std::vector<double>& times, double t, double max_diff) {
  if (times.empty()) return std::nullopt;
  const size_t k = nearestTimeIndex(times, t);
  if (std::abs(times[k] - t) > max_diff) return std::nullopt;
  return k;
}

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

double rms(const std::vector<double>& values) {
  if (values.empty()) return kNaN;
  double sum = 0;
  for (double v : values) sum += v * v;
  return std::sqrt(sum / static_cast<double>(values.size()));
}

nlohmann::json finiteOrNull(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace

int boardCornersInView(const CameraModel& camera, const std::vector<Vec3>& corners_world, const SE3& T_world_camera,
                       double margin_px) {
  const SE3 T_camera_world = T_world_camera.inverse();
  int in_view = 0;
  for (const Vec3& p_world : corners_world) {
    const Vec3 p_camera = T_camera_world * p_world;
    in_view += p_camera.z() > 0 && camera.inImage(camera.project(p_camera), margin_px);
  }
  return in_view;
}

double gapAllowanceM(double path_since_board_m) { return std::max(0.005, 0.01 * path_since_board_m); }

std::vector<BoardViewFrame> boardViewFrames(const std::vector<double>& frame_timestamps, const Trajectory& groundtruth,
                                            const Trajectory& estimate, const CameraModel& camera,
                                            const ChessboardTarget& target, double max_diff) {
  const std::vector<double> t_groundtruth = timestampsInOrder(groundtruth, "ground truth");
  const std::vector<double> t_estimate = timestampsInOrder(estimate, "trajectory.txt");
  double own_pose = max_diff;  // how near in time the estimate's pose of a frame is
  for (size_t k = 1; k < frame_timestamps.size(); ++k)
    if (const double dt = frame_timestamps[k] - frame_timestamps[k - 1]; dt > 0) own_pose = std::min(own_pose, dt / 4);
  const std::vector<Vec3> corners_world = target.cornersWorld();
  std::vector<BoardViewFrame> frames;
  std::optional<Vec3> last_centre;
  for (size_t k = 0; k < frame_timestamps.size(); ++k) {
    const double t = frame_timestamps[k];
    const auto truth = nearestWithin(t_groundtruth, t, max_diff);
    if (!truth) continue;
    const SE3& T_world_camera = groundtruth[*truth].T_world_camera;
    BoardViewFrame f;
    f.frame = static_cast<int>(k);
    f.corners_in_view = boardCornersInView(camera, corners_world, T_world_camera);
    if (last_centre) f.step_m = (T_world_camera.t() - *last_centre).norm();
    last_centre = T_world_camera.t();
    if (const auto posed = nearestWithin(t_estimate, t, own_pose))
      f.error_m = (estimate[*posed].T_world_camera.t() - T_world_camera.t()).norm();
    frames.push_back(f);
  }
  return frames;
}

BoardVisibilityScores scoreBoardVisibility(const std::vector<BoardViewFrame>& frames, int corners) {
  BoardVisibilityScores s;
  s.corners = corners;
  const int n = static_cast<int>(frames.size());
  bool seen = false, in_gap = false, was_away = false;
  std::optional<int> return_index;  // into frames
  double path_since_board = 0;
  std::vector<double> partial, returning_partial, whole, settled, after_return;
  for (int i = 0; i < n; ++i) {
    const BoardViewFrame& f = frames[i];
    if (f.corners_in_view == 0) {
      was_away = was_away || seen;
      if (seen) {
        path_since_board += f.step_m;
        if (!in_gap) s.gaps.push_back({f.frame, f.frame, 0, kNaN, kNaN}), in_gap = true;
        BoardGap& g = s.gaps.back();
        g.last = f.frame;
        if (!f.error_m) {
          ++g.lost;
        } else {
          const double ratio = *f.error_m / gapAllowanceM(path_since_board);
          if (!(ratio <= g.worst_over_allowance)) g.worst_over_allowance = ratio, g.worst_error_m = *f.error_m;
        }
      }
      continue;
    }
    seen = true;
    in_gap = false;
    path_since_board = 0;
    if (was_away && !return_index && f.corners_in_view == corners) return_index = i;
    if (!f.error_m) continue;
    if (f.corners_in_view == corners) whole.push_back(*f.error_m);
    else if (2 * f.corners_in_view >= corners) {
      partial.push_back(*f.error_m);
      if (was_away) returning_partial.push_back(*f.error_m);
    }
    if (f.corners_in_view != corners || i < kSettledFrom) continue;
    bool long_in_view = true;
    for (int j = std::max(0, i - kSettledMargin); j <= std::min(n - 1, i + kSettledMargin) && long_in_view; ++j)
      long_in_view = frames[j].corners_in_view == corners;
    if (long_in_view) settled.push_back(*f.error_m);
  }
  if (return_index) {
    s.return_frame = frames[*return_index].frame;
    for (int i = *return_index; i < std::min(n, *return_index + kReturnFrames); ++i) {
      if (frames[i].error_m) after_return.push_back(*frames[i].error_m);
      else ++s.after_return_lost;
    }
  }
  s.after_return_rms = rms(after_return);
  s.settled_rms = rms(settled);
  s.partial_rms = rms(partial);
  s.returning_partial_rms = rms(returning_partial);
  s.whole_rms = rms(whole);
  s.partial_frames = static_cast<int>(partial.size());
  s.returning_partial_frames = static_cast<int>(returning_partial.size());
  s.whole_frames = static_cast<int>(whole.size());
  return s;
}

nlohmann::json boardVisibilityToJson(const BoardVisibilityScores& s) {
  nlohmann::json gaps = nlohmann::json::array();
  for (const BoardGap& g : s.gaps)
    gaps.push_back({{"first", g.first},
                    {"last", g.last},
                    {"lost", g.lost},
                    {"worst_error", finiteOrNull(g.worst_error_m)},
                    {"worst_over_allowance", finiteOrNull(g.worst_over_allowance)}});
  return {{"corners", s.corners},
          {"gaps", gaps},
          {"return_frame", s.return_frame ? nlohmann::json(*s.return_frame) : nlohmann::json(nullptr)},
          {"after_return_lost", s.return_frame ? nlohmann::json(s.after_return_lost) : nlohmann::json(nullptr)},
          {"after_return_rms", finiteOrNull(s.after_return_rms)},
          {"settled_rms", finiteOrNull(s.settled_rms)},
          {"after_return_over_settled", finiteOrNull(s.after_return_rms / s.settled_rms)},
          {"partial_rms", finiteOrNull(s.partial_rms)},
          {"returning_partial_rms", finiteOrNull(s.returning_partial_rms)},
          {"whole_rms", finiteOrNull(s.whole_rms)},
          {"partial_over_whole", finiteOrNull(s.partial_rms / s.whole_rms)},
          {"partial_frames", s.partial_frames},
          {"returning_partial_frames", s.returning_partial_frames},
          {"whole_frames", s.whole_frames}};
}

}  // namespace slamcmp
