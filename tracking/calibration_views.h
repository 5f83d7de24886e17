#pragma once
// Self-calibration on a back-end's first frames when no camera file is given (cslam's and
// hybrid's): each frame's view of the whole board is offered to Zhang's calibration until one is
// accepted; the frames that showed the board are then posed from their own corners, late
// (LatePose, "board"), so a self-calibrated run loses no frame that showed the board.
#include <deque>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <opencv2/core.hpp>

#include "core/self_calibration.h"
#include "core/tracker.h"
#include "geometry/homography_pose.h"

namespace slamcmp {

class CalibrationViews {
 public:
  // The last options.max_late_poses frames that showed the board are kept for posing.
  CalibrationViews(const ChessboardTarget& target, cv::Size image_size, const SelfCalibrationOptions& options,
                   const BoardPoseOptions& board_pose);

  // One frame: its corners (the whole board, SPEC order, distorted pixels), or nullptr when it did
  // not show the board. A symmetric board's origin is kept by continuity with the last view.
  // Returns the calibration once one is accepted: tried when the views fill the calibrator, or
  // there are enough of them after max_frames frames; else nothing, and `refused` says why a
  // calibration tried on this frame was not used.
  std::optional<CalibrationResult> add(int frame_index, const std::vector<cv::Point2f>* corners,
                                       std::string* refused);
  // After the calibration: the frames before `frame_index` that showed the board, posed from their
  // corners with `camera` (the gathered frames are then forgotten).
  std::vector<LatePose> latePoses(const CameraModel& camera, int frame_index);

  // A gathering frame's reason: the views so far, and why a calibration tried on it was refused.
  std::string gatheringReason(const std::string& refused) const;
  // Why a run ended uncalibrated.
  std::string whyNotCalibrated() const { return calibrator_.whyNotCalibrated(); }

 private:
  struct Gathered {
    int frame_index;
    std::vector<cv::Point2f> uv;
  };
  ChessboardTarget target_;
  SelfCalibrationOptions options_;
  BoardPoseOptions board_pose_;
  SelfCalibrator calibrator_;
  int frames_ = 0;
  std::deque<Gathered> gathered_;
  std::vector<cv::Point2f> last_uv_;  // the last view's corners: a symmetric board's origin follows them
};

// summary.json's `self_calibration`, for the back-ends that calibrate themselves.
nlohmann::json selfCalibrationJson(const CameraModel& camera, double rms_px);

}  // namespace slamcmp
