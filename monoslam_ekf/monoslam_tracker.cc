#include "monoslam_ekf/monoslam_tracker.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/chessboard.h"
#include "core/error.h"
#include "core/stage_timer.h"
#include "ekf/motion_model.h"
#include "geometry/homography_pose.h"

namespace slamcmp {

namespace {

// A board-free run's camera position std is mostly that of its unobservable scale (it grows with
// the distance from the first camera whatever the tracking does): only the measurement count
// tells its frames lost.
ReportingOptions reportingFor(const MonoslamOptions& options, InitSource init) {
  ReportingOptions reporting = options.filter.reporting;
  if (init == InitSource::None) reporting.max_position_sigma = std::numeric_limits<double>::infinity();
  return reporting;
}

// The four outer inner corners' pixels (ChessboardTarget::outerCornersWorld order) among all the
// inner corners (SPEC section 2 order).
std::vector<Vec2> outerCornerPixels(const ChessboardTarget& target, const std::vector<cv::Point2f>& uv_distorted) {
  const int c = target.cols, r = target.rows;
  const int index[4] = {0, c - 1, (r - 1) * c + c - 1, (r - 1) * c};
  std::vector<Vec2> out;
  for (int i : index) out.emplace_back(uv_distorted[i].x, uv_distorted[i].y);
  return out;
}

}  // namespace

MonoslamTracker::MonoslamTracker(const TrackerContext& context, const MonoslamOptions& options)
    : options_(options),
      init_(context.init),
      want_overlay_(context.want_overlay),
      slam_(context.camera ? *context.camera : CameraModel(), options.filter, context.init == InitSource::None,
            context.init == InitSource::None ? &options.relocalisation : nullptr),
      reporting_(reportingFor(options, context.init)) {
  if (!context.camera)
    throw InputError("--camera", "the monoslam back-end needs a calibrated camera (camera.yaml)");
  camera_ = *context.camera;
  if (init_ == InitSource::None) {  // no target: the first frame's features start the map
    if (options_.two_view_orientation.enabled) two_view_.emplace(camera_, options_.two_view_orientation);
    return;
  }
  if (options_.two_view_orientation.enabled)
    throw InputError("monoslam.two_view_orientation.enabled", "is for board-free runs only (--init none)");
  if (!context.target)
    throw InputError("--target", "the monoslam back-end needs the board (target.yaml): its corners start the map");
  target_ = *context.target;
  board_detector_.emplace(target_, options_.board, options_.board_presence);
  if (init_ != InitSource::Board) {
    if (!context.T_world_camera_init)
      throw InputError("--init", "groundtruth and manual initialisation need the first camera pose");
    T_world_camera_init_ = context.T_world_camera_init;
  }
}

nlohmann::json MonoslamTracker::options() const { return optionsToJson(options_); }

void MonoslamTracker::finish() {
  if (!ever_started_ && init_ != InitSource::None)
    throw InputError("", "monoslam never started: no frame showed the " + std::to_string(target_.cols) + "x" +
                             std::to_string(target_.rows) + " chessboard (--init board needs it in view)");
}

bool MonoslamTracker::startWithoutMap(const Frame& frame, std::string* reason) {
  // A restart would begin a new world frame at a new scale, unrelated to the poses before it.
  if (ever_started_) {
    *reason = "a board-free run does not restart";
    return false;
  }
  // The world frame is the first camera's, known exactly; the scale is the inverse-depth prior's.
  slam_.reset(SE3(), Eigen::Matrix<double, 13, 13>::Zero());
  started(frame.timestamp);
  unknown_first_motion_ = true;
  return true;
}

void MonoslamTracker::setFirstMotionPrior(double dt) {
  unknown_first_motion_ = false;
  if (!(dt > 0)) dt = options_.filter.motion.default_dt;
  // Nothing has correlated the velocities with the rest yet: their blocks of P are diagonal.
  const StartOptions& s = options_.start;
  Eigen::MatrixXd& P = slam_.state().P();
  P.diagonal().segment<3>(EkfState::kV).setConstant(std::pow(s.board_free_move_per_frame / dt, 2));
  P.diagonal().segment<3>(EkfState::kW).setConstant(std::pow(s.board_free_turn_per_frame / dt, 2));
}

bool MonoslamTracker::start(const Frame& frame, std::string* reason) {
  start_pose_from_board_ = false;
  if (init_ == InitSource::None) return startWithoutMap(frame, reason);
  std::vector<cv::Point2f> corners;
  const bool board_seen = board_detector_->detect(frame.grey, &corners);
  // A symmetric board's origin: the one nearest where the given pose, the restart's first view
  // or the last pose before a loss puts it (else chooseSymmetricOrder's convention).
  const bool use_given_pose = init_ != InitSource::Board && !ever_started_;
  std::optional<SE3> reference;
  if (use_given_pose) reference = T_world_camera_init_;
  else if (restart_view_) reference = restart_view_->T_world_camera;
  else reference = last_pose_;
  if (board_seen && target_.symmetric() && reference)
    chooseSymmetricOrder(target_, corners, projectBoardCorners(camera_, target_, *reference));
  start_corners_.clear();
  if (board_seen)
    for (const cv::Point2f& c : corners) start_corners_.emplace_back(c.x, c.y);
  SE3 T_world_camera;
  // The given pose starts the run; every restart after a loss needs the board.
  if (use_given_pose) {
    T_world_camera = *T_world_camera_init_;
  } else if (board_seen) {
    T_world_camera = wholeBoardPose(camera_, target_, corners, {}).T_camera_board.inverse();
    start_pose_from_board_ = true;
  } else {
    restart_view_.reset();
    *reason = "no board seen";
    return false;
  }
  // A restart after a loss (SceneLib has none) may come mid-turn, where a camera taken for still
  // loses the board's corners again (wall_turn turns back at 0.4 rad/s): it waits for the board in
  // a second frame running and starts moving as the board moved between the two.
  const StartOptions& s = options_.start;
  CameraVelocity velocity;
  double sigma_v = s.velocity_sigma, sigma_w = s.angular_velocity_sigma;
  if (ever_started_) {
    const std::optional<StampedPose> previous = std::exchange(restart_view_, StampedPose{frame.timestamp, T_world_camera});
    const double dt = previous ? frame.timestamp - previous->timestamp : 0;
    if (!(dt > 0)) {
      *reason = "board seen: the restart waits for the next frame's view to know the motion";
      return false;
    }
    // Two views that disagree (a detection gone wrong in one) give a speed the health check stops.
    velocity = velocityBetween(previous->T_world_camera, T_world_camera, dt);
    sigma_v = s.restart_move_per_frame / dt;
    sigma_w = s.restart_turn_per_frame / dt;
  }

  const bool manual = init_ == InitSource::Manual && !ever_started_;
  const double sigma_r = manual ? s.manual_position_sigma : s.position_sigma;
  const double sigma_q = manual ? s.manual_orientation_sigma : s.orientation_sigma;
  slam_.reset(T_world_camera, cameraCovariance(sigma_r, sigma_q, sigma_v, sigma_w));
  slam_.state().x().segment<3>(EkfState::kV) = velocity.v_world;
  slam_.state().x().segment<3>(EkfState::kW) = velocity.w_camera;

  // The known features: the board's outer inner corners, exact, with patches from this frame (at
  // the detected corners, or where the given pose projects them when the board is not detected).
  const std::vector<Vec3> corners_world = target_.outerCornersWorld();
  const std::vector<Vec2> detected = board_seen ? outerCornerPixels(target_, corners) : std::vector<Vec2>{};
  for (size_t k = 0; k < corners_world.size(); ++k) {
    Vec2 uv;
    if (board_seen) {
      uv = detected[k];
    } else {
      const Vec3 p_camera = T_world_camera.inverse() * corners_world[k];
      if (p_camera.z() <= 0) continue;
      uv = camera_.project(p_camera);
    }
    slam_.addKnownPoint(frame.grey, uv, corners_world[k], Vec3(0, 0, -1));  // printed face towards -z
  }
  started(frame.timestamp);
  return true;
}

void MonoslamTracker::started(double timestamp) {
  restart_view_.reset();
  trusted_id_limit_ = slam_.nextFeatureId();  // the start's features (board corners) included
  ever_started_ = true;
  resumed(timestamp);
}

void MonoslamTracker::resumed(double timestamp) {
  running_ = true;
  diverged_ = false;
  reporting_.reset();
  frames_unmeasured_ = 0;
  last_timestamp_ = timestamp;
}

std::string MonoslamTracker::divergence() const {
  const std::string why = slam_.divergence();
  if (!why.empty()) return why;
  if (frames_unmeasured_ >= options_.filter.health.max_frames_unmeasured)
    return "no feature matched for " + std::to_string(frames_unmeasured_) + " frames";
  return "";
}

bool MonoslamTracker::relocalise(const Frame& frame, FrameResult* result) {
  int inliers = 0;
  const std::optional<SE3> T_world_camera = slam_.relocalise(frame.grey, trusted_id_limit_, &inliers);
  if (!T_world_camera) return false;
  const RelocalisationOptions& ro = options_.relocalisation;
  // The motion after a loss is as unknown as the first one: its prior is set per frame interval
  // once the next frame gives the interval (setFirstMotionPrior).
  slam_.relocate(*T_world_camera, cameraCovariance(ro.position_sigma, ro.orientation_sigma, 0, 0), trusted_id_limit_);
  if (two_view_) two_view_->forget();  // the orientation jumped
  unknown_first_motion_ = true;
  resumed(frame.timestamp);
  result->reason = "relocalised against the map (" + std::to_string(inliers) + " points agree)";
  return true;
}

FrameResult MonoslamTracker::track(const Frame& frame) {
  FrameResult result;
  // A lost board-free run is anchored again only by its map, found again by relocalisation. The
  // filter runs on meanwhile, its features mapped while posed kept; whatever its own searches do
  // to them, the relocalisation's PnP check decides.
  const bool relocalising = lost_ && slam_.relocalises();
  bool relocalised = false;
  double relocalise_ms = -1;
  if (relocalising && (frames_lost_ - 1) % options_.relocalisation.interval == 0) {  // from the first lost frame
    const double start = threadCpuMs();
    relocalised = relocalise(frame, &result);
    relocalise_ms = threadCpuMs() - start;
  }
  slam_.protectFeaturesBelow(relocalising && !relocalised ? trusted_id_limit_ : 0);
  result = trackFrame(frame, relocalised, std::move(result));
  if (relocalise_ms >= 0) {  // a search of the map's features in the whole frame
    const auto features = std::find_if(result.stages.begin(), result.stages.end(),
                                       [](const auto& stage) { return stage.first == "features"; });
    if (features != result.stages.end())
      features->second += relocalise_ms;
    else
      result.stages.emplace_back("features", relocalise_ms);
  }
  lost_ = ever_started_ && !result.T_world_camera;
  frames_lost_ = lost_ ? frames_lost_ + 1 : 0;
  return result;
}

void MonoslamTracker::rememberOrientation(const PoseCovariance& pose_covariance) {
  two_view_->remember(slam_.T_world_camera().R(), pose_covariance.bottomRightCorner<3, 3>().trace() / 3);
}

// The frame that starts (or restarts) the filter: false, the result said, when it cannot start here.
bool MonoslamTracker::startFrame(const Frame& frame, FrameResult* result) {
  std::string reason;
  if (!start(frame, &reason)) {
    result->status = ever_started_ ? TrackStatus::Lost : TrackStatus::Initialising;
    result->reason = ever_started_ ? lost_reason_ + "; " + reason : reason;
    if (want_overlay_ && !start_corners_.empty()) {  // a restart's first view of the board
      result->overlay = FrameOverlay();
      result->overlay->board_corners = wholeBoardCorners(start_corners_);
    }
    return false;
  }
  if (two_view_) two_view_->update(frame.grey, slam_.state());  // the first tracks
  slam_.updateMap(frame.grey, visible_);
  // A board-free map starts from its first frame's features, and never restarts: a frame without
  // any (a covered lens, a blank wall) would start an empty map and lose the whole run. The start
  // waits for texture. (A textured frame may give only a few: the initialisation adds features a
  // few boxes a frame, 3 in tum_fr1_rpy's first.)
  if (init_ == InitSource::None && slam_.features().empty()) {
    ever_started_ = false;
    running_ = false;
    result->status = TrackStatus::Initialising;
    result->reason = "waiting for texture to start the map: no feature found";
    return false;
  }
  if (want_overlay_) {
    result->overlay = slam_.overlay(FrameMeasurement(), target_);
    result->overlay->board_corners = wholeBoardCorners(start_corners_);
  }
  return true;
}

// A running filter's frame: predicted, measured, its map updated. False, the result said, when the
// filter diverged.
bool MonoslamTracker::filterFrame(const Frame& frame, bool relocalised, FrameResult* result,
                                  FrameMeasurement* measurement) {
  {
    const StageTimer timer(&result->stages, "predict");
    if (!relocalised) {  // else placed in this frame
      if (unknown_first_motion_) setFirstMotionPrior(frame.timestamp - last_timestamp_);
      slam_.predict(frame.timestamp - last_timestamp_);
    }
  }
  last_timestamp_ = frame.timestamp;
  if (two_view_) {  // the orientation first: the patches are then searched about the turn the tracks measured
    const StageTimer timer(&result->stages, "two_view");
    two_view_->update(frame.grey, slam_.state());
  }
  {
    const StageTimer timer(&result->stages, "features");
    *measurement = slam_.measure(frame.grey);
  }
  visible_ = measurement->visible;
  result->measured = measurement->matched;
  // Before updateMap, which may remove features `measurement` points into.
  trusted_matched_ = 0;
  for (const FeatureSearch& s : measurement->features)
    if (s.outcome == SearchOutcome::Matched && slam_.features()[s.index].id < trusted_id_limit_) ++trusted_matched_;
  if (want_overlay_) result->overlay = slam_.overlay(*measurement, target_);
  frames_unmeasured_ = result->measured > 0 ? 0 : frames_unmeasured_ + 1;
  {
    const StageTimer timer(&result->stages, "map");
    slam_.updateMap(frame.grey, visible_);
  }
  const std::string why = divergence();
  if (!why.empty()) {
    running_ = false;
    diverged_ = true;
    lost_reason_ = why;
    result->status = TrackStatus::Lost;
    result->reason = why;
    return false;
  }
  return true;
}

FrameResult MonoslamTracker::trackFrame(const Frame& frame, bool relocalised, FrameResult result) {
  FrameMeasurement measurement;         // none in a start's frame
  const bool started_here = !running_;  // the pose comes from the board (or the given pose) in this frame
  if (started_here ? !startFrame(frame, &result) : !filterFrame(frame, relocalised, &result, &measurement))
    return result;
  result.features = static_cast<int>(slam_.features().size());
  // Nothing absolute anchors a board-free map but the map itself: after a loss its frames are posed
  // again once features mapped while it was posed are found again (while it tracks, matching them
  // anchors nothing: its innovations are tested as any run's). With relocalisation, only by it (a PnP
  // check over the map): the filter's own searches from a lost pose, with wide ellipses, match
  // look-alikes (tum_fr1_rpy: frames reported 20 to 97 degrees off). Features mapped while its
  // frames were lost agree with whatever pose it drifted to, and prove nothing.
  const bool found_again =
      lost_ && (slam_.relocalises() ? relocalised : trusted_matched_ >= options_.filter.reporting.min_measured);
  const bool anchored = started_here || (init_ == InitSource::None && found_again);
  if (const std::string weak =
          reporting_.weakness(result.measured, measurement.nis, measurement.nis_dof, anchored, slam_.state());
      !weak.empty()) {
    result.status = TrackStatus::Lost;  // its extrapolation is not a pose
    result.reason = weak;
    // The filter runs on (two_view_ is board-free only) and its orientation with it: a loss is of
    // its anchor, while the tracks still measure its turn, and its pose guides the relocalisation's
    // second search (Relocaliser::relocalise).
    if (two_view_) rememberOrientation(slam_.poseCovariance());
    // Nothing but the board anchors a map started from it: its filter restarts from the board's
    // next view rather than run on unanchored. A board-free one runs on (relocalisation above).
    if (init_ != InitSource::None) {
      running_ = false;
      lost_reason_ = weak;
    }
    return result;
  }
  trusted_id_limit_ = slam_.nextFeatureId();
  slam_.rememberPosedMap();
  result.status = TrackStatus::Tracked;
  result.source = started_here && start_pose_from_board_ ? "board" : "ekf";
  result.T_world_camera = last_pose_ = slam_.T_world_camera();
  result.pose_covariance = slam_.poseCovariance();
  if (two_view_) rememberOrientation(*result.pose_covariance);
  if (result.measured == 0 && frames_unmeasured_ > 0 && !relocalised)
    result.reason = "no feature matched: prediction only";
  return result;
}

std::vector<MapPoint> MonoslamTracker::mapPoints() const {
  // A filter lost by its reporting keeps its map until a restart replaces it; one that diverged
  // has none worth writing.
  if (!ever_started_ || diverged_) return {};
  return slam_.mapPoints();
}

BackendRegistration monoslamBackend() {
  BackendRegistration r = makeRegistration<MonoslamOptions>(
      "monoslam", "the MonoSLAM baseline (Davison 2007, SceneLib defaults): EKF, particle depths, 11x11 patches",
      {{"ekf", "monoslam", "#000000", "MonoSLAM"}}, /*takes_init=*/true,
      [](const TrackerContext& context, const MonoslamOptions& options) {
        return std::make_unique<MonoslamTracker>(context, options);
      });
  r.stages = {"predict", "features", "map"};
  r.optional_stages = {"two_view"};  // board-free runs with two_view_orientation, between predict and features
  return r;
}

}  // namespace slamcmp
