#pragma once
// Many image features tracked from frame to frame as a measurement of the hybrid filter: Shi-Tomasi
// features tracked by pyramidal Lucas-Kanade, used two ways.
// - The window (ekf/msckf_update.h): each camera pose of a sliding window is cloned into the
//   state's tail, and every stretch of a track that ends (lost, or as long as the window) is used
//   in an MSCKF update of the window's poses. A track that goes on starts its next stretch at the
//   last observation of the one used, as frame-to-frame odometry does: that observation is in two
//   updates, whose noise the filter takes as independent (pixel_sigma, set from the runs, absorbs
//   it). Two close views leave a turn traded against a step across the view, the mode the board
//   leaves open too.
// - Points (tracked_points.h): a score of the tracks held in the state's tail as inverse-depth
//   points and measured in every frame; their tracks are not in the window.
#include <deque>
#include <unordered_map>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "ekf/ekf_state.h"
#include "ekf/msckf_update.h"
#include "hybrid/tail_layout.h"
#include "hybrid/tracked_points.h"
#include "tracking/feature_tracker.h"

namespace slamcmp {

struct TrackedMotionOptions {
  // Off by default. Full presets, seed 1 (README), with the defaults to session 20
  // (cv::cornerSubPix's corners at 0.2 px; since then the defaults are as accurate with the board
  // in view without the tracks, which are for the frames without it): the tracks with their
  // points lower hybrid's error with the board in view (tv1 0.68 -> 0.42 mm, tv2 0.73 -> 0.39),
  // carry it through the board's departure where the dozen patch features did not (board_leaves
  // seed 2 2.18 -> 0.81), and pose the frames facing another wall (wall_turn, 1.3-1.6 % of the
  // path off), but roll_distortion goes from 0.20 to 0.72 mm and board_leaves seed 3 from 3.7 to
  // 4.4, and a frame costs about twice as much.
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
  double snooping_probability = 0;  // each track tested against the others (msckf_update.h); 0: off
  FeatureTrackerOptions tracks{80, 50};  // at most 80 tracked, replenished below 50
  // Tracks held as points (tracked_points.h), started on tracks that are none while fewer are held.
  TrackedPointsOptions points;
  template <class V>
  void visit(V& v) {
    v("enabled", enabled, "update the filter with features tracked over a sliding window of cloned poses (MSCKF) and as points");
    v("window", window, "camera poses held in the state for the tracks, the current one's included");
    v("min_track_length", min_track_length, "a track seen in fewer frames is not used");
    v("pixel_sigma", pixel_sigma, "a tracked point's noise per coordinate, pixels");
    v("gate_probability", gate_probability,
      "chi-squared test of a track's residual, and of a point's innovation: it is left out beyond this quantile");
    v("min_parallax_deg", min_parallax_deg, "a track whose first and last rays are closer than this is not triangulated, degrees");
    v("max_triangulation_px", max_triangulation_px, "a triangulated track missing one of its frames by more is left out, pixels");
    v("without_board", without_board, "also update the frames in which no board corner is measured");
    v("snooping_probability", snooping_probability,
      "test each track against all the others at this probability and drop the worst until none fails (0: off)");
    v("tracks", tracks, "the tracked Shi-Tomasi features");
    v("points", points, "tracks held in the state as inverse-depth points (tracked_points.h)");
  }
  void check() const;
  MsckfOptions msckf() const {
    return {pixel_sigma, gate_probability, min_parallax_deg, max_triangulation_px, snooping_probability};
  }
};

class TrackedMotion {
 public:
  // Tracks by Lucas-Kanade over pyramids built for lk_window and lk_levels.
  TrackedMotion(const CameraModel& camera, const TrackedMotionOptions& options, cv::Size lk_window, int lk_levels);

  // After the frame's other updates, before the map grows or shrinks: the tracks followed into
  // `grey` (its `pyramid`; started where the filter's rotation since the last clone puts them),
  // the points measured, the camera cloned, the tracks that ended used in one update, the oldest
  // clone dropped from the window, the tracks replenished, new points started. The points are
  // measured in every frame, the window updates only frames `anchored` by the board (unless
  // without_board): without it two close views are blind to the scale. Returns how many points
  // were measured.
  int update(EkfState& state, const cv::Mat& grey, const std::vector<cv::Mat>& pyramid, bool anchored);
  // The tracks start again, and the clones and points still in the state's tail are dropped (none
  // after the filter restarted; a relocated camera's are stale).
  void reset(EkfState& state);

 private:
  CameraModel camera_;
  TrackedMotionOptions options_;
  cv::Size lk_window_;
  int lk_levels_;
  FeatureTracker tracker_;
  std::vector<cv::Mat> pyramid_previous_;
  TailLayout tail_;
  std::deque<int> clones_;  // the window's clones, oldest first, by number
  int next_clone_ = 0;
  std::unordered_map<int, std::vector<std::pair<int, Vec2>>> seen_;  // feature id -> (clone, uv) since its last use
  TrackedPoints points_;
};

}  // namespace slamcmp
