#pragma once
// The one interface every back-end implements (STYLE: data flows one way).
//   Sequence -> Frame -> Tracker::track -> FrameResult -> RunRecorder -> eval
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/frame_overlay.h"
#include "core/sequence.h"
#include "core/stage_timer.h"
#include "core/target.h"

namespace slamcmp {

// Method-neutral: a frame is posed (Tracked, with the pose's source in the back-end's own words),
// still starting (Initialising) or Lost (with its reason).
enum class TrackStatus { Tracked, Initialising, Lost };
const char* toString(TrackStatus status);  // "tracked", "initialising", "lost"

// frames.csv's status column: the pose's source for a tracked frame ("board", "two_view", "ekf"),
// else "initialising" or "lost".
std::string statusLabel(TrackStatus status, const std::string& source);

// A pose found later for an earlier frame the tracker returned as Initialising (cslam and hybrid:
// frames that showed the board while they gathered self-calibration views, posed once the camera
// is known: tracking/calibration_views.h).
struct LatePose {
  int frame_index = 0;
  std::string source;  // as FrameResult::source
  SE3 T_world_camera;
  int measured = 0;
};

// A pose's covariance as (position, rotation vector), metres and radians: the rotation error is the
// world-frame rotation taking the estimate to the truth, R_true = exp(e) R_estimate.
using PoseCovariance = Eigen::Matrix<double, 6, 6>;

struct FrameResult {
  TrackStatus status = TrackStatus::Lost;
  std::string source;                 // Tracked: where the pose came from ("board", "two_view", "ekf")
  std::optional<SE3> T_world_camera;  // empty when lost or initialising: never a made-up pose
  std::optional<PoseCovariance> pose_covariance;  // filters: the pose's uncertainty (for NEES)
  int features = 0;                   // features the back-end holds (tracked or in the map)
  int measured = 0;                   // features measured in this frame
  std::string reason;                 // why the frame is lost or degraded; "" when all is well
  std::optional<FrameOverlay> overlay;  // what was seen, when TrackerContext::want_overlay
  std::vector<LatePose> late_poses;     // earlier Initialising frames posed now (see RunRecorder)
  StageTimes stages;                    // CPU ms of the back-end's stages in this frame (summary.json)
};

struct MapPoint {
  int id = 0;
  Vec3 p_world;
  int observations = 0;  // frames the feature was measured in
  double sigma = -1;     // position standard deviation in metres (EKF); -1 if not known
};

// None: no target; the back-end starts from the first frame's features at an arbitrary scale
// (its world frame is the first camera's; evaluated with Sim(3) alignment).
enum class InitSource { Board, GroundTruth, Manual, None };

// Everything a back-end gets; it reads no file and parses no command line itself.
struct TrackerContext {
  std::optional<CameraModel> camera;       // none: the back-end self-calibrates or refuses
  std::optional<ChessboardTarget> target;  // the board that defines the world frame
  std::string mode;                        // one of the back-end's registered modes, never ""
  InitSource init = InitSource::Board;     // back-ends registered with takes_init only
  std::optional<SE3> T_world_camera_init;  // for GroundTruth and Manual initialisation
  cv::Size image_size;
  bool want_overlay = false;  // fill FrameResult::overlay (run --overlay / --show)
};

// A keyframe as a back-end refined it: its frame and pose.
struct KeyframePose {
  int frame_index = 0;
  SE3 T_world_camera;
};

class Tracker {
 public:
  virtual ~Tracker() = default;
  virtual std::string name() const = 0;
  // One call per frame, in order. frame.grey is CV_8UC1 and never empty.
  virtual FrameResult track(const Frame& frame) = 0;
  // The map as it stands (world frame).
  virtual std::vector<MapPoint> mapPoints() const { return {}; }
  // A back-end that keeps keyframes: those it still holds, oldest first, as refined so far. They
  // may have moved since their frame was posed (a map re-anchored).
  virtual std::vector<KeyframePose> keyframePoses() const { return {}; }
  // The options in force, recorded in summary.json.
  virtual nlohmann::json options() const { return nlohmann::json::object(); }
  // Called once after the last frame. Throws InputError (without a file name: the caller adds
  // the sequence's) when the run as a whole was impossible with this input, e.g. the board never
  // appeared and the mode needs it.
  virtual void finish() {}
};

}  // namespace slamcmp
