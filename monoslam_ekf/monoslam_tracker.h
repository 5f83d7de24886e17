#pragma once
// The MonoSLAM EKF back-end (thesis chapter 2, SPEC section 5) behind the Tracker interface.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/backend_registry.h"
#include "core/tracker.h"
#include "core/trajectory.h"
#include "ekf/ekf_slam.h"
#include "ekf/pose_reporting.h"
#include "monoslam_ekf/monoslam_options.h"

namespace slamcmp {

class MonoslamTracker : public Tracker {
 public:
  // Throws InputError without a camera, without a target (but for --init none), or without
  // T_world_camera_init for groundtruth/manual initialisation. `options` are checked (checkOptions).
  // --init none: the world frame is the first camera's and the map starts from that frame's
  // features in inverse depth, at the scale of their prior (ekf/inverse_depth.h).
  MonoslamTracker(const TrackerContext& context, const MonoslamOptions& options);

  std::string name() const override { return "monoslam"; }
  FrameResult track(const Frame& frame) override;
  std::vector<MapPoint> mapPoints() const override;
  nlohmann::json options() const override;
  // Throws InputError when the filter never started: with --init board, no frame showed the board.
  void finish() override;

 private:
  bool start(const Frame& frame, std::string* reason);
  bool startWithoutMap(const Frame& frame, std::string* reason);  // --init none
  void started(double timestamp);  // the filter runs from this frame on
  // The filter runs again from this frame (a start, a relocalisation): the run's counters afresh.
  void resumed(double timestamp);
  // --init none: the velocity prior (StartOptions::board_free_*) once the first interval dt is known.
  void setFirstMotionPrior(double dt);
  std::string divergence() const;  // why the filter cannot be trusted, "" if it can
  // The lost camera found again against the map mapped while it was posed (relocalisation.*);
  // the filter then runs from that pose. False when it was not (*result untouched).
  bool relocalise(const Frame& frame, FrameResult* result);
  // This frame's tracks and the filter's orientation after its update, for the next frames'
  // two-view orientation.
  void rememberOrientation(const PoseCovariance& pose_covariance);
  // One frame of the filter (track() after any relocalisation; `result` holds its stages so far).
  FrameResult trackFrame(const Frame& frame, bool relocalised, FrameResult result);
  bool startFrame(const Frame& frame, FrameResult* result);
  bool filterFrame(const Frame& frame, bool relocalised, FrameResult* result, FrameMeasurement* measurement);

  CameraModel camera_;
  ChessboardTarget target_;
  MonoslamOptions options_;
  InitSource init_;
  bool want_overlay_ = false;
  std::optional<SE3> T_world_camera_init_;
  std::optional<PresenceGatedDetector> board_detector_;  // with a board (not --init none)
  std::optional<TwoViewOrientation> two_view_;  // --init none with two_view_orientation.enabled

  EkfSlam slam_;
  PoseReporting reporting_;
  bool running_ = false;
  bool diverged_ = false;  // the filter stopped on its health check (no map worth writing)
  bool ever_started_ = false;
  bool start_pose_from_board_ = false;  // the last start's pose is the board's (frames.csv's source)
  std::string lost_reason_;
  std::vector<Vec2> start_corners_;  // the board corners detected by the last start, for the overlay
  std::optional<SE3> last_pose_;     // the last pose given out: a restart keeps a symmetric board's origin
  std::optional<StampedPose> restart_view_;  // a restart's board view in the frame before, for its motion
  double last_timestamp_ = 0;
  int frames_unmeasured_ = 0;
  bool unknown_first_motion_ = false;  // --init none, before the second frame (or after a relocalisation)
  int trusted_id_limit_ = 0;  // features with smaller ids were mapped while the frames were posed
  int trusted_matched_ = 0;   // of them, matched this frame
  int visible_ = 0;  // map points predicted in the image this frame
  bool lost_ = false;        // the last frame was not posed (after the start)
  int frames_lost_ = 0;      // since the last posed frame
};

// The back-end's registration (core/backend_registry.h): one mode, "ekf".
BackendRegistration monoslamBackend();

}  // namespace slamcmp
