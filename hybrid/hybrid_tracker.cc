#include "hybrid/hybrid_tracker.h"

#include "core/chessboard.h"
#include "core/error.h"
#include "core/options.h"
#include "ekf/ekf_update.h"
#include "geometry/homography_pose.h"

namespace slamcmp {


void HybridStartOptions::check() const {
  for (const auto& [field, sigma] : {std::pair{"position_sigma", position_sigma},
                                     {"orientation_sigma", orientation_sigma},
                                     {"velocity_sigma", velocity_sigma},
                                     {"angular_velocity_sigma", angular_velocity_sigma}})
    if (!(sigma > 0 && sigma < 100)) throw OptionError(field, "must be a standard deviation in (0, 100)");
}

HybridTracker::HybridTracker(const TrackerContext& context, const HybridOptions& options)
    : options_(options),
      image_size_(context.image_size),
      want_overlay_(context.want_overlay),
      reporting_(options.filter.reporting) {
  if (!context.target)
    throw InputError("--target", "hybrid needs the chessboard target (target.yaml beside the sequence or --target)");
  target_ = *context.target;
  if (context.camera) {
    camera_ = context.camera;
    image_size_ = cv::Size(camera_->width, camera_->height);
    startFilter(*camera_);
  } else {
    calibration_views_.emplace(target_, image_size_, options_.calibration, BoardPoseOptions{});
  }
}

void HybridTracker::startFilter(const CameraModel& camera) {
  slam_ = std::make_unique<EkfSlam>(
      camera, options_.filter);
  corners_ = std::make_unique<BoardCornerMeasurer>(camera, target_, options_.corners,
                                                   options_.filter.search.rolling_shutter_readout);
  motion_ = std::make_unique<TrackedMotion>(camera, options_.tracked_motion, corners_->lkWindow(), corners_->lkLevels(),
                                            options_.filter.search.rolling_shutter_readout);
}

nlohmann::json HybridTracker::options() const {
  nlohmann::json j = optionsToJson(options_);
  if (calibration_rms_px_) j["self_calibration"] = selfCalibrationJson(*camera_, *calibration_rms_px_);
  return j;
}

void HybridTracker::finish() {
  if (ever_started_ || posed_late_) return;  // frames posed, by the filter or from their corners
  if (!camera_)
    throw InputError("", calibration_views_->whyNotCalibrated());
  throw InputError("", "hybrid never started: no frame showed the " + std::to_string(target_.cols) + "x" +
                           std::to_string(target_.rows) + " chessboard");
}

bool HybridTracker::calibrate(const Frame& frame, FrameResult* result) {
  std::vector<cv::Point2f> corners;
  const bool seen = detectChessboard(frame.grey, target_, &corners, options_.corners.detector);
  std::string refused;  // why a calibration tried on this frame was not used
  if (const auto calibration = calibration_views_->add(frame.index, seen ? &corners : nullptr, &refused)) {
    camera_ = calibration->camera;
    calibration_rms_px_ = calibration->rms_px;
    // The frames that showed the board, posed from it; this one starts the filter. A symmetric
    // board's origin carries on from them (start() keeps it nearest the last pose).
    result->late_poses = calibration_views_->latePoses(*camera_, frame.index);
    posed_late_ = !result->late_poses.empty();
    if (!result->late_poses.empty()) last_pose_ = result->late_poses.back().T_world_camera;
    calibration_views_.reset();
    startFilter(*camera_);
    return true;
  }
  result->status = TrackStatus::Initialising;
  result->reason = calibration_views_->gatheringReason(refused);
  return false;
}

bool HybridTracker::start(const Frame& frame, BoardCornerMeasurement* board, std::string* reason) {
  std::vector<cv::Point2f> uv = corners_->searchWholeImage(frame.grey);
  if (uv.empty()) {
    *reason = "no board seen";
    return false;
  }
  if (target_.symmetric() && last_pose_) chooseSymmetricOrder(target_, uv, projectBoardCorners(*camera_, target_, *last_pose_));
  if (!startFromCorners(frame, uv, board)) {
    *reason = "the board's corners do not fit one pose";
    return false;
  }
  return true;
}

bool HybridTracker::startFromCorners(const Frame& frame, const std::vector<cv::Point2f>& uv,
                                     BoardCornerMeasurement* board) {
  // The board's own pose (thesis eqs. 3.1 to 3.17) sets the mean; this frame's corners then
  // update it, so the start's covariance is the board's.
  const BoardPose board_pose = wholeBoardPose(*camera_, target_, uv, BoardPoseOptions{});
  const HybridStartOptions& s = options_.start;
  slam_->reset(board_pose.T_camera_board.inverse(),
               cameraCovariance(s.position_sigma, s.orientation_sigma, s.velocity_sigma, s.angular_velocity_sigma));
  corners_->restart();
  motion_->reset(slam_->state());
  *board = corners_->measureDetected(slam_->state(), frame.grey, uv);
  if (board->observations.empty() || !corners_->update(slam_->state(), board))
    return false;
  running_ = true;
  ever_started_ = true;
  reporting_.reset();
  frames_since_search_ = 0;
  last_timestamp_ = frame.timestamp;
  return true;
}

BoardCornerMeasurement HybridTracker::measureBoard(const Frame& frame, bool* restarted) {
  const BoardCornerMeasurementOptions& co = options_.corners;
  BoardCornerMeasurement board = corners_->measure(slam_->state(), frame.grey);
  if (!board.observations.empty() && corners_->update(slam_->state(), &board)) {
    frames_since_search_ = 0;
    // Corners coming into view, where the updated filter now puts them within a pixel or two.
    BoardCornerMeasurement entering = corners_->measureNew(slam_->state(), frame.grey);
    if (!entering.observations.empty() && corners_->update(slam_->state(), &entering)) {
      board.observations.insert(board.observations.end(), entering.observations.begin(), entering.observations.end());
      board.corner_ids.insert(board.corner_ids.end(), entering.corner_ids.begin(), entering.corner_ids.end());
    }
    return board;
  }
  // Found where the filter predicts it but outside its gates, else not there: the whole image
  // every search_interval frames (a full search of a textured frame without the board costs
  // 100-350 ms; the presence test first, 5 ms).
  std::vector<cv::Point2f> found = corners_->boardOutsideGates();
  corners_->reset();
  if (found.empty() && ++frames_since_search_ >= co.search_interval) {
    frames_since_search_ = 0;
    found = corners_->searchWholeImage(frame.grey);
    if (!found.empty() && target_.symmetric() && last_pose_) chooseSymmetricOrder(target_, found, projectBoardCorners(*camera_, target_, *last_pose_));
  }
  if (found.empty()) return BoardCornerMeasurement();
  // The board found where the filter did not expect it: the filter was too sure of the camera (a
  // turn faster than its motion model, a drift; vamr's hand jerks under the adapted motion noise:
  // 12 frames of 736 lost their board before it was taken from the predicted region at once). Its
  // camera covariance is widened and the corners re-anchor the camera and, through the
  // correlations, the map; if they still disagree, the filter restarts from the board. An adapted
  // motion noise goes back to its set values.
  slam_->distrustMotion();
  corners_->setMotionNoise(slam_->motionNoise());
  Eigen::MatrixXd& P = slam_->state().P();
  P.diagonal().segment<3>(EkfState::kR).array() += co.reanchor_position_sigma * co.reanchor_position_sigma;
  P.diagonal().segment<4>(EkfState::kQ).array() += co.reanchor_orientation_sigma * co.reanchor_orientation_sigma;
  board = corners_->measureDetected(slam_->state(), frame.grey, found);
  // Most of the found corners must fit the widened filter (kMinFoundCornersFitting).
  if (board.observations.size() >= kMinFoundCornersFitting * found.size() && corners_->update(slam_->state(), &board))
    return board;
  *restarted = true;
  if (!startFromCorners(frame, found, &board)) return BoardCornerMeasurement();
  return board;
}

FrameOverlay HybridTracker::overlay(const FrameMeasurement& measurement, const BoardCornerMeasurement& board) const {
  FrameOverlay o = slam_->overlay(measurement, target_);
  for (size_t k = 0; k < board.observations.size(); ++k)
    o.board_corners.push_back({board.corner_ids[k], board.observations[k].z});
  return o;
}

FrameResult HybridTracker::track(const Frame& frame) {
  FrameResult result;
  if (!camera_ && !calibrate(frame, &result)) return result;
  FrameMeasurement measurement;
  BoardCornerMeasurement board;
  int points_measured = 0;  // tracked points (tracked_motion.h), when on
  if (!running_) {
    std::string reason;
    if (!start(frame, &board, &reason)) {
      if (corners_) {  // no corner kept this frame: the exposure's history says so
        corners_->reset();
        corners_->endFrame(frame.timestamp, frame.grey);
      }
      result.status = ever_started_ ? TrackStatus::Lost : TrackStatus::Initialising;
      result.reason = ever_started_ ? lost_reason_ + "; " + reason : reason;
      return result;
    }
    corners_->endFrame(frame.timestamp, frame.grey);
    if (want_overlay_) result.overlay = overlay(measurement, board);  // the corners it started from
    motion_->update(slam_->state(), frame.grey, corners_->pyramid(), true);
    slam_->updateMap(frame.grey, visible_, boardPixels());
  } else {
    {
      const StageTimer timer(&result.stages, "predict");
      slam_->predict(frame.timestamp - last_timestamp_);
      corners_->setMotionNoise(slam_->motionNoise());
    }
    last_timestamp_ = frame.timestamp;
    // The board first: its corners are exact landmarks, and the map's search regions then shrink.
    bool restarted = false;
    {
      const StageTimer timer(&result.stages, "board");
      board = measureBoard(frame, &restarted);
      corners_->endFrame(frame.timestamp, frame.grey);
    }
    if (restarted) result.reason = "the board disagreed with the filter: restarted from the board";
    {
      const StageTimer timer(&result.stages, "features");
      measurement = slam_->measure(frame.grey);
    }
    visible_ = measurement.visible;
    if (want_overlay_) result.overlay = overlay(measurement, board);
    // The tracks after the other updates (the pose they clone is this frame's best), before the
    // map grows or shrinks. Timed whether on or not (a stage the registration names is always
    // there: off, it costs nothing).
    {
      const StageTimer timer(&result.stages, "tracks");
      points_measured = motion_->update(slam_->state(), frame.grey, corners_->pyramid(), !board.observations.empty());
    }
    {
      const StageTimer timer(&result.stages, "map");
      slam_->updateMap(frame.grey, visible_, boardPixels());
    }
    const std::string why = slam_->divergence();
    if (!why.empty()) {
      running_ = false;
      lost_reason_ = why;
      corners_->reset();
      result.status = TrackStatus::Lost;
      result.reason = why;
      return result;
    }
  }
  result.measured = measurement.matched + static_cast<int>(board.observations.size()) + points_measured;
  result.features = static_cast<int>(slam_->features().size());
  const std::string weak = reporting_.weakness(result.measured, measurement.nis, measurement.nis_dof,
                                               !board.observations.empty(), slam_->state());
  if (!weak.empty()) {  // the filter runs on; this frame's pose is not worth reporting
    result.status = TrackStatus::Lost;
    result.reason = weak;
    return result;
  }
  result.status = TrackStatus::Tracked;
  result.source = board.observations.empty() ? "ekf" : "board";
  result.T_world_camera = last_pose_ = slam_->T_world_camera();
  result.pose_covariance = slam_->poseCovariance();
  return result;
}

std::vector<Vec2> HybridTracker::boardPixels() const {
  // The board's squares and margin: its corners and a ring one square outside them.
  std::vector<Vec2> pixels;
  const double s = target_.square_size;
  for (int j = -1; j <= target_.rows; ++j)
    for (int i = -1; i <= target_.cols; ++i) {
      const Vec3 p_camera = slam_->T_world_camera().inverse() * Vec3(i * s, j * s, 0);
      if (p_camera.z() > 0.05) pixels.push_back(camera_->project(p_camera));
    }
  return pixels;
}

std::vector<MapPoint> HybridTracker::mapPoints() const {
  if (!running_) return {};
  return slam_->mapPoints();
}

BackendRegistration hybridBackend() {
  BackendRegistration r = makeRegistration<HybridOptions>(
      "hybrid", "MonoSLAM's EKF with every board corner a known landmark: re-anchored whenever the board is seen",
      {{"ekf", "hybrid", "#9467bd"}}, /*takes_init=*/false,
      [](const TrackerContext& context, const HybridOptions& options) {
        return std::make_unique<HybridTracker>(context, options);
      });
  r.stages = {"predict", "board", "features", "tracks", "map"};
  return r;
}

}  // namespace slamcmp
