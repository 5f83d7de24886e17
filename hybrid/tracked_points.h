#pragma once
// Tracks held in the hybrid filter's state as points in inverse depth (Civera 2008; OpenVINS's SLAM
// features), in its tail (tail_layout.h). Each starts on a Lucas-Kanade track, with the camera's
// covariance and a broad inverse depth, and is measured in every frame by Lucas-Kanade from the
// image it started in, begun where its track is now: a chain of frame-to-frame steps drifts (0.06 px
// rms off a fixed point over tv1, 0.4 px over tv3's zoom), which a point held for hundreds of
// frames takes for motion. Lucas-Kanade only shifts a patch, so a point whose first image no longer
// looks like it starts again on its track. Its depth, learnt over the whole track, tells a turn from
// a step across the view, which two close views cannot, and the points carry the filter where the
// board leaves. The pixel a point starts at has just been in the window's update of its track
// (tracked_motion.h): the same shared-observation approximation as the window's.
#include <map>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "ekf/ekf_state.h"
#include "hybrid/tail_layout.h"
#include "tracking/feature_tracker.h"

namespace slamcmp {

struct TrackedPointsOptions {
  int max = 20;                     // points held at most (0: none)
  double pixel_sigma = 0.3;         // pixels, a point's measurement noise per coordinate
  double rho = 1.0;                 // 1/m, a new point's inverse depth (1 m) ...
  double rho_sigma = 1.0;           // 1/m, ... and its std: from 0.33 m to beyond infinity at 2 sigma
  // Found from its first image farther than this from its track, a point starts again on it.
  double max_anchor_px = 1.0;
  // Likewise when its first image's patch, scaled by the change of its distance and turned by the
  // roll since, would move its window's corners by more than this (held through tv3's zoom, points
  // were 0.4 px off a fixed point and tv3's error went 0.76 -> 1.65 mm).
  double max_deformation_px = 0.4;
  template <class V>
  void visit(V& v) {
    v("max", max, "tracks kept in the state as inverse-depth points, measured every frame (0: none)");
    v("pixel_sigma", pixel_sigma, "pixels, a point's measurement noise per coordinate");
    v("rho", rho, "1/m, a new point's inverse depth");
    v("rho_sigma", rho_sigma, "1/m, std of a new point's inverse depth");
    v("max_anchor_px", max_anchor_px, "pixels; a point found from its first image this far from its track starts again");
    v("max_deformation_px", max_deformation_px,
      "pixels; a point whose first image, scaled and turned as the camera moved since, moves its window's corners "
      "this much starts again");
  }
  void check() const;
};

class TrackedPoints {
 public:
  // Each point's innovation is gated at gate_probability (chi-squared, 2 dof).
  // rolling_shutter_readout (s): each point predicted where its row is read (ekf/rolling_shutter.h),
  // a new one's first pixel turned back to its frame's time; 0, a global shutter.
  TrackedPoints(const CameraModel& camera, const TrackedPointsOptions& options, double gate_probability,
                cv::Size lk_window, int lk_levels, double rolling_shutter_readout = 0);

  // The points measured where this frame's tracks (`features`, in `pyramid`) and their first
  // images put them, gated one by one and updated together. Removed: those whose track ended,
  // those that no longer look like their first image (they start again), those failing the gate
  // (a track gone astray or a moving point: never started again). Returns how many were measured.
  int measure(EkfState& state, TailLayout& tail, const std::vector<Feature>& features,
               const std::vector<cv::Mat>& pyramid);
  // New points on tracks that are none, while fewer than `max` are held. Returns their ids.
  std::vector<int> start(EkfState& state, TailLayout& tail, const std::vector<Feature>& features,
                         const std::vector<cv::Mat>& pyramid);
  bool holds(int track_id) const { return points_.count(track_id) > 0; }
  // Tracks that ended: their refusals are forgotten.
  void forget(const std::vector<int>& ended);
  void clear();

 private:
  struct Point {
    int first = 0;            // the frame it started in (first_images_)
    cv::Point2f first_uv;     // where
    Mat3 R_world_first;       // the camera's orientation then
  };
  // Pixels by which the point's first-image patch, scaled by the change of its distance and turned
  // by the roll since, moves the corners of a window of this half diagonal.
  double patchDeformation(const EkfState& state, int offset, const Point& point, double half_diagonal) const;

  CameraModel camera_;
  TrackedPointsOptions options_;
  double gate_;  // chi-squared, 2 dof
  double readout_ = 0;
  cv::Size lk_window_;
  int lk_levels_;
  std::unordered_map<int, Point> points_;            // by track id
  std::map<int, std::vector<cv::Mat>> first_images_;  // frame -> its pyramid, while points started there
  std::unordered_set<int> refused_;                  // track ids whose point failed its gate
  int frame_ = 0;                                    // start() calls
};

}  // namespace slamcmp
