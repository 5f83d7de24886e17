#pragma once
// Combined mode: the board pose of each frame fused with the frame-to-frame motion of the tracked
// features (a Kalman filter on the camera pose). A single view of the board leaves a noisy
// direction (its tilt traded against translation); the features' relative motion is precise from
// frame to frame but drifts. The board keeps the fused pose absolute, the motion keeps it smooth.
#include <optional>

#include "core/geometry.h"
#include "geometry/pose_refinement.h"

namespace slamcmp {

struct BoardOdometryFusionOptions {
  bool enabled = true;
  double min_pixel_sigma = 0.02;   // floor on the noise estimated from the reprojection residuals, pixels
  // The motion's covariance over its Gauss-Newton estimate from the map residuals. Those residuals
  // hold the map's error, which cancels in the frame-to-frame motion, so the estimate overstates
  // the motion's noise: 0.1 measured best on tv1..tv4 (0.5: ATE 5 to 15 % higher).
  double motion_noise_scale = 0.1;
  // Tracked features drift as the image moves fast (their patches change with the view): the
  // motion's covariance grows by (1 + (rotation / this)^2). 1 degree kept tv1..tv4 as they were
  // and halved the error through board_leaves' pan.
  double fast_rotation_deg = 1.0;
  // The map's scale is uncertain (young, a point triangulated at little parallax), and so is the
  // length of every frame's motion, by the same fraction and sign from frame to frame: without
  // this the motion's translation drags the fused pose along the path. 0.02 took board_partial's
  // second seed from 0.41 to 0.34 mm ATE (partial-board frames 0.50 -> 0.39) and wall_turn's
  // return from 0.99 to 0.78 of the settled error; tv1..tv4 within 0.03 mm; 0.05 the same.
  double motion_scale_sigma = 0.02;
  // A point of the features' motion that either frame's pose leaves further off than this (and
  // than 3 times the median) is dropped and the motion refitted: residuals are 0.05-0.15 px on
  // the presets, a feature tracked astray 0.5-5 px. board_leaves (seeds 1, 2, 3), ATE 0.76 ->
  // 0.75, 0.67 -> 0.64, 1.16 -> 0.92 mm, its half-board frames 0.97 -> 0.31, 1.17 -> 0.77, 0.98
  // -> 0.97 mm; tv1..tv4 the same or better; 0.3 about the same.
  double max_motion_residual_px = 0.5;
  // A gross-error gate, far beyond chi2(6) (22.5 is its 99.9 %): tighter gates fire on the far
  // frames of tv3 and tv4, where the board's own noise grows, and cost 15 to 25 % of ATE.
  double max_mahalanobis2 = 100;  // board against prediction beyond this: prediction inflated
  // Which of the two is wrong beyond the gate: a board pose that disagrees in one frame is taken
  // for the outlier (the prediction stands), one that disagrees again for a moved map (the
  // prediction gives way). wall_turn seed 2, a whole board 3.3 mm off in a quiet frame (216)
  // pulled the fused pose 1.2 mm off for 10 frames: the 30 frames after its return 1.30 -> 0.81
  // times the settled error; the gate fires in 0-6 of ~200 board frames on the presets.
  int max_held_frames = 1;
  // When the board returns after a gap the filter restarts from the board and the refined map
  // together, as its first corners come back and again as its whole view re-anchors the map, and
  // the map's points are trusted to this fraction of the path travelled since the board last
  // anchored the map (the presets' gaps drift 0.15-0.6 %). 0: as if they had not drifted,
  // which suits cv::cornerSubPix's corners (a strip's pose leans with their bias); with the
  // gradient corners 0.002 takes board_leaves' half boards (seeds 1-3) from 0.31-0.92 to 0.23-0.39
  // mm (configs/cslam_gradient.yaml).
  double map_drift_fraction = 0;
  template <class V>
  void visit(V& v) {
    v("enabled", enabled, "fuse each board pose with the features' frame-to-frame motion (combined mode)");
    v("min_pixel_sigma", min_pixel_sigma,
      "floor on the pixel noise estimated from the reprojection residuals (board and map), pixels");
    v("motion_noise_scale", motion_noise_scale,
      "the frame-to-frame motion's covariance over its Gauss-Newton estimate (two map poses and map drift)");
    v("fast_rotation_deg", fast_rotation_deg,
      "the motion's covariance grows by 1 + (its rotation / this)^2 (features drift in fast turns), degrees");
    v("motion_scale_sigma", motion_scale_sigma,
      "relative uncertainty of the map's scale: the motion's translation is uncertain by this fraction along itself");
    v("max_motion_residual_px", max_motion_residual_px,
      "a map point the motion's pose in either frame misses by more than this (and 3 times the median) is dropped "
      "and the motion refitted, pixels");
    v("max_mahalanobis2", max_mahalanobis2,
      "squared Mahalanobis distance between board pose and prediction beyond which the prediction's covariance "
      "is inflated until they agree");
    v("max_held_frames", max_held_frames,
      "frames in a row whose board pose beyond max_mahalanobis2 is taken for an outlier (the prediction stands) "
      "before the prediction gives way (0: it always gives way)");
    v("map_drift_fraction", map_drift_fraction,
      "when the board returns after a gap (its first corners, its whole view re-anchoring the map), the map's "
      "points are trusted to this fraction of the path travelled since it last anchored the map (0: as if they "
      "had not drifted)");
  }
  void check() const;
};

// A pose with its covariance (6x6, left perturbation of T_camera_world as in refinePose).
struct PoseWithCovariance {
  SE3 T_camera_world;
  Mat6 covariance = Mat6::Identity();
};

// The covariance of a pose fitted to reprojections: sigma^2 (J^T J)^-1, sigma estimated from the
// residual RMS over n points (floored at min_sigma_px).
PoseWithCovariance poseWithCovariance(const SE3& T_camera_world, const std::vector<Vec3>& p_world,
                                      const std::vector<Vec2>& xy_normalised, double focal_px, double rms_px,
                                      double min_sigma_px);

// The features' poses in the previous frame and in this one against the same map points: their
// difference is the frame-to-frame motion (the map's error cancels in it).
struct MapMotion {
  PoseWithCovariance previous, current;
};

class BoardOdometryFusion {
 public:
  explicit BoardOdometryFusion(const BoardOdometryFusionOptions& options) : options_(options) {}

  // One frame with the board, and the features' motion from the previous frame when it was
  // measured. Returns the fused T_camera_world. Without a motion to fuse with (or a filter to
  // move by it) the filter (re)starts from `start` if given (a better pose of this frame than the
  // board's alone), else from the board pose.
  SE3 update(const PoseWithCovariance& board, const std::optional<MapMotion>& map_motion,
             const PoseWithCovariance* start = nullptr);
  bool restarting() const { return !fused_; }
  // Whether the last update held the prediction against a board pose beyond the gate.
  bool heldLastBoard() const { return held_ > 0; }
  // Starts the filter again from this frame's pose (e.g. the map under it was corrected).
  void restartFrom(const PoseWithCovariance& pose) {
    fused_ = pose;
    held_ = 0;
  }
  // A frame without the board (or not posed): the next board frame restarts the filter.
  void reset();

 private:
  BoardOdometryFusionOptions options_;
  std::optional<PoseWithCovariance> fused_;  // the previous frame's
  int held_ = 0;  // frames in a row the prediction was held against the board
};

}  // namespace slamcmp
