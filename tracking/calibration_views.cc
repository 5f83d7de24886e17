#include "tracking/calibration_views.h"

#include "core/chessboard.h"

namespace slamcmp {

CalibrationViews::CalibrationViews(const ChessboardTarget& target, cv::Size image_size,
                                   const SelfCalibrationOptions& options, const BoardPoseOptions& board_pose)
    : target_(target),
      options_(options),
      board_pose_(board_pose),
      calibrator_(target, image_size, options) {}

std::optional<CalibrationResult> CalibrationViews::add(int frame_index, const std::vector<cv::Point2f>* corners,
                                                       std::string* refused) {
  ++frames_;
  if (corners) {
    std::vector<cv::Point2f> uv = *corners;
    if (target_.symmetric() && !last_uv_.empty()) chooseSymmetricOrder(target_, uv, last_uv_);
    calibrator_.addView(uv);
    last_uv_ = uv;
    gathered_.push_back({frame_index, std::move(uv)});
    if (static_cast<int>(gathered_.size()) > options_.max_late_poses) gathered_.pop_front();
  }
  const bool enough = calibrator_.numViews() >= options_.min_views;
  if (!calibrator_.full() && !(enough && frames_ >= options_.max_frames)) return std::nullopt;
  return calibrator_.calibrate(refused);
}

std::vector<LatePose> CalibrationViews::latePoses(const CameraModel& camera, int frame_index) {
  std::vector<LatePose> late;
  for (const Gathered& g : gathered_) {
    if (g.frame_index >= frame_index) continue;
    const BoardPose pose = wholeBoardPose(camera, target_, g.uv, board_pose_);
    late.push_back({g.frame_index, "board", pose.T_camera_board.inverse(), static_cast<int>(g.uv.size())});
  }
  gathered_.clear();
  return late;
}

std::string CalibrationViews::gatheringReason(const std::string& refused) const {
  return "gathering board views for self-calibration (" + std::to_string(calibrator_.numViews()) + " of " +
         std::to_string(options_.min_views) + ")" + (refused.empty() ? "" : "; " + refused);
}

nlohmann::json selfCalibrationJson(const CameraModel& camera, double rms_px) {
  return {{"fx", camera.fx}, {"fy", camera.fy}, {"cx", camera.cx}, {"cy", camera.cy}, {"rms_px", rms_px}};
}

}  // namespace slamcmp
