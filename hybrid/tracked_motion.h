#pragma once
// Many image features tracked from frame to frame as a measurement of the hybrid filter
// (ekf/msckf_update.h): Shi-Tomasi features tracked by pyramidal Lucas-Kanade, each camera pose of
// a sliding window cloned into the state, and every stretch of a track that ends (lost, or as
// long as the window) used in an MSCKF update of the window's poses. A track that goes on starts
// its next stretch at the last observation of the one used, as frame-to-frame odometry does: that
// observation is in two updates, whose noise the filter takes as independent (pixel_sigma, set
// from the runs, absorbs it). The dozen patch features the filter maps hold the absolute pose
// apart from the board; these eighty tracks hold the window's poses together, which averages the
// board's per-frame noise over frames as cslam's fused motion does.
#include <deque>
#include <unordered_map>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "ekf/ekf_state.h"
#include "ekf/msckf_update.h"
#include "tracking/feature_tracker.h"

namespace slamcmp {

struct TrackedMotionOptions {
  // Off by default: with the board in view the tracks lower hybrid's error on 12 of 13 preset
  // runs (tv1..tv4 0.68 / 0.73 / 0.76 / 1.65 -> 0.58 / 0.48 / 0.70 / 1.59 mm, board_partial 0.30
  // to 0.40 -> 0.29 to 0.32), but where the board leaves in a fast pan the filter's few young
  // patch features decide whether it carries on, and any change of its path there flips that:
  // board_leaves at 200 frames loses 73 frames with them (200 posed without), and without them
  // with another feature seed goes 3 mm off instead.
  bool enabled = false;
  // Camera poses cloned in the state, the current one's included. 2, each frame-to-frame step of
  // every track used in the frame it is made, did best: with 8 (ATE tv1..tv4 0.64 / 0.70 / 0.88 /
  // 1.59 mm against 0.54 / 0.43 / 0.84 / 1.55) the current pose learns from the few tracks that
  // end in its frame only.
  int window = 2;
  int min_track_length = 2;     // a track seen in fewer frames is not used
  // A track's noise per coordinate, pixels. Tracks on the renders are within 0.015 px of their
  // epipolar lines, but the filter around them is not that exact (its board corners assumed at
  // 0.2 px, found to 0.05): 0.12-0.3 px measured best, 0.3 the steadiest over 13 presets.
  double pixel_sigma = 0.3;
  double gate_probability = 0.99;
  double min_parallax_deg = 0;  // two frames apart, a track's rays are nearly parallel
  double max_triangulation_px = 2.0;
  // Also update the frames without board corners. Measured (window 2-4, 7 runs of board_leaves
  // and wall_turn): better on some runs, worse on others (board_leaves seed 3 NEES 5-11).
  bool without_board = false;
  FeatureTrackerOptions tracks{80, 50};  // at most 80 tracked, replenished below 50
  template <class V>
  void visit(V& v) {
    v("enabled", enabled, "update the filter with features tracked over a sliding window of cloned poses (MSCKF)");
    v("window", window, "camera poses held in the state for the tracks, the current one's included");
    v("min_track_length", min_track_length, "a track seen in fewer frames is not used");
    v("pixel_sigma", pixel_sigma, "a tracked point's noise per coordinate, pixels");
    v("gate_probability", gate_probability, "chi-squared test of a track's residual: it is left out beyond this quantile");
    v("min_parallax_deg", min_parallax_deg, "a track whose first and last rays are closer than this is not triangulated, degrees");
    v("max_triangulation_px", max_triangulation_px, "a triangulated track missing one of its frames by more is left out, pixels");
    v("without_board", without_board, "also update the frames in which no board corner is measured");
    v("tracks", tracks, "the tracked Shi-Tomasi features");
  }
  void check() const;
  MsckfOptions msckf() const { return {pixel_sigma, gate_probability, min_parallax_deg, max_triangulation_px}; }
};

class TrackedMotion {
 public:
  // Tracks by Lucas-Kanade over pyramids built for lk_window and lk_levels.
  TrackedMotion(const CameraModel& camera, const TrackedMotionOptions& options, cv::Size lk_window, int lk_levels);

  // After the frame's other updates, before the map grows or shrinks: the tracks followed into
  // `grey` (its `pyramid`; started where the filter's rotation since the last clone puts them), the camera
  // cloned, the tracks that ended used in one update, the oldest clone dropped from the window,
  // the tracks replenished. Only frames `anchored` by the board are updated (unless
  // without_board): without it the tracks' constraints are blind to the scale.
  MsckfResult update(EkfState& state, const cv::Mat& grey, const std::vector<cv::Mat>& pyramid, bool anchored);
  // The tracks start again, and the clones still in the state's tail are dropped (none after the
  // filter restarted; a relocated camera's are stale).
  void reset(EkfState& state);

 private:
  int cloneOffset(const EkfState& state, int clone) const;

  CameraModel camera_;
  TrackedMotionOptions options_;
  cv::Size lk_window_;
  int lk_levels_;
  FeatureTracker tracker_;
  std::vector<cv::Mat> pyramid_previous_;
  std::deque<int> clones_;  // the window's clones, oldest first, by number (the state's tail, in order)
  int next_clone_ = 0;
  std::unordered_map<int, std::vector<std::pair<int, Vec2>>> seen_;  // feature id -> (clone, uv) since its last use
};

}  // namespace slamcmp
