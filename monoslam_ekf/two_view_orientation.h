#pragma once
// The board-free filter's orientation measured by two-view geometry to each of the last frames
// (geometry/multi_baseline_rotation.h) on Lucas-Kanade tracks of its own. A filter whose features
// are young (a hand-held camera turning fast) cannot see the parallax of the camera's swing about
// the hand, and takes part of it for rotation; an essential matrix estimates the rotation together
// with the translation (tum_fr1_rpy: docs/findings.md, session 32).
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "ekf/ekf_state.h"
#include "geometry/multi_baseline_rotation.h"
#include "tracking/feature_tracker.h"

namespace slamcmp {

// More and closer features than the tracker's defaults: on tum_fr1_rpy 150 of them gave 3.8-4.4
// degrees where 250 give 1.9-2.1 (seeds 0-1).
inline FeatureTrackerOptions twoViewTrackOptions() {
  FeatureTrackerOptions o;
  o.max_features = 250;
  o.min_features = 150;
  o.min_distance_px = 10;
  return o;
}

struct TwoViewOrientationOptions {
  bool enabled = false;    // off: the SceneLib filter as it was
  // The measured orientation's std per axis, degrees, to which the last remembered frame's orientation
  // variance is added: the views' orientations are the filter's own, correlated with its state in
  // ways it does not hold, and taken as exact they made it too sure of its turn (tum_fr1_rpy seeds
  // 0-7 at 0.2 degrees: 1380 of 2000 frames posed, 1777 with the variance added).
  double sigma_deg = 0.2;
  int lk_window_px = 21;   // Lucas-Kanade window side, pixels
  // Pyramid levels above the image: with 3, tum_fr1_rpy seeds 0-15 posed 85 % of frames, with 2
  // 97 % at the same accuracy (docs/findings.md, session 33).
  int lk_levels = 2;
  FeatureTrackerOptions tracks = twoViewTrackOptions();
  MultiBaselineRotationOptions rotation;
  template <class V>
  void visit(V& v) {
    v("enabled", enabled, "--init none: the orientation also measured by two-view geometry to the last frames");
    v("sigma_deg", sigma_deg,
      "degrees, the measured orientation's std per axis (the last remembered frame's orientation variance is added)");
    v("lk_window_px", lk_window_px, "Lucas-Kanade window side, pixels");
    v("lk_levels", lk_levels, "Lucas-Kanade pyramid levels above the image");
    v("tracks", tracks, "the features tracked for the two-view geometry");
    v("rotation", rotation, "the orientation composed from the earlier views");
  }
  void check() const;
  void checkImage(cv::Size image) const;  // the Lucas-Kanade window fits in the image
};

class TwoViewOrientation {
 public:
  TwoViewOrientation(const CameraModel& camera, const TwoViewOrientationOptions& options);

  // Tracks this frame's features from the last one's and, with the earlier frames remembered,
  // updates the state's orientation.
  void update(const cv::Mat& grey, EkfState& state);
  // update()'s first half: this frame's pyramid and tracks (moved on from the last frame's and
  // replenished), undistorted in tracks().
  void track(const cv::Mat& grey);
  const FrameTracks& tracks() const { return tracks_; }
  // The frame just updated: its tracks and the filter's orientation (after every update) are kept
  // for later frames; rotation_variance (rad^2, per axis) is that orientation's.
  void remember(const Mat3& R_world_camera, double rotation_variance);
  // The filter's orientation jumped (a relocation): no later frame composes an orientation through
  // the earlier ones.
  void forget() { rotation_.clear(); }

 private:
  CameraModel camera_;
  TwoViewOrientationOptions options_;
  FeatureTracker tracker_;
  MultiBaselineRotation rotation_;
  std::vector<cv::Mat> pyramid_;  // the last frame's
  FrameTracks tracks_;            // this frame's, undistorted
  double reference_variance_ = 0;  // the last remembered frame's orientation variance, rad^2 per axis
};

}  // namespace slamcmp
