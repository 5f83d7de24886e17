#pragma once
// Self-calibration from the board (Zhang 2000 via cv::calibrateCamera): board views are gathered
// as they come, keeping only views that differ from all kept ones (corner positions, board size
// and tilt in the image), then intrinsics and distortion are estimated from them.
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/chessboard.h"
#include "core/sequence.h"
#include "core/target.h"

namespace slamcmp {

struct SelfCalibrationOptions {
  int max_views = 25;               // calibrate with at most this many views
  int min_views = 8;                // views needed before calibrating
  int max_frames = 150;             // frames to gather views from before calibrating with what is there
  double min_view_change = 0.03;    // a view is new when its corners moved by this (RMS) fraction of the image diagonal
  int distortion_terms = 5;         // 4 (k1 k2 p1 p2) or 5 (and k3)
  double max_rms_px = 1.5;          // a calibration fitting worse is refused (e.g. a wrong board size)
  // Boards seen at nearly one orientation (parallel views: a camera sliding or rolling in front of
  // it) do not determine the focal length (Zhang 2000, section 3.3): 8 views of board_partial within
  // 3.5 degrees fitted fx 950 for 525 at 0.05 px rms. The calibration sets measure 50-100 degrees
  // (Bouguet's, OpenCV's, the phone video), vamr_checkerboard 22.
  double min_view_spread_deg = 10;  // the largest angle between two views' board normals, at least
  int max_late_poses = 1000;  // frames that showed the board while views were gathered, posed once calibrated
  template <class V>
  void visit(V& v) {
    v("max_views", max_views, "board views used at most");
    v("min_views", min_views, "board views needed to calibrate");
    v("max_frames", max_frames, "frames over which views are gathered before calibrating with what there is");
    v("min_view_change", min_view_change,
      "a view is kept if its corners moved (RMS) this fraction of the image diagonal from every kept view");
    v("distortion_terms", distortion_terms, "4 (k1 k2 p1 p2) or 5 (also k3)");
    v("max_rms_px", max_rms_px, "a calibration whose reprojection error exceeds this is refused, pixels");
    v("min_view_spread_deg", min_view_spread_deg,
      "degrees; views whose board normals all lie closer than this to each other (parallel views) are refused: "
      "they do not determine the focal length");
    v("max_late_poses", max_late_poses,
      "frames that showed the board while views were gathered, posed from their corners once calibrated (the last "
      "this many)");
  }
  void check() const;
};

struct CalibrationResult {
  CameraModel camera;
  double rms_px = 0;  // reprojection error over all views
  int views = 0;
  std::string note;  // which distortion terms were fixed at 0 beyond those asked, and why ("" if none)
};

class SelfCalibrator {
 public:
  SelfCalibrator(const ChessboardTarget& target, cv::Size image_size, const SelfCalibrationOptions& options);

  // Offers a board view (corners in SPEC order, distorted pixels); true if it was kept.
  bool addView(const std::vector<cv::Point2f>& uv_distorted);
  int numViews() const { return static_cast<int>(views_.size()); }
  bool full() const { return numViews() >= options_.max_views; }
  // Zhang's calibration on the kept views, refitted with fewer radial terms where the distortion
  // folds over the image (core/distortion_fold.h); empty with fewer than min_views, an error over
  // max_rms_px, parallel views or a fold even with k1 alone, and then `why_not` (if given) says which.
  std::optional<CalibrationResult> calibrate(std::string* why_not = nullptr);
  // The error of a run that ends uncalibrated (no camera file given): why no calibration came of
  // the views, the last calibration's refusal or too few views if none was tried.
  std::string whyNotCalibrated() const;

 private:
  ChessboardTarget target_;
  cv::Size image_size_;
  SelfCalibrationOptions options_;
  std::vector<std::vector<cv::Point2f>> views_;
  std::string last_refusal_;
};

// `slamcmp calibrate`: a full board search in every frame of `frames` (its corners refined as
// `detector` says), the view selection above, then Zhang's calibration. Throws InputError naming
// `where` when too few distinct board views were found.
CalibrationResult calibrateFromFrames(FrameSource& frames, const ChessboardTarget& target, cv::Size image_size,
                                      const SelfCalibrationOptions& options, const std::string& where,
                                      const ChessboardDetectorOptions& detector = {});

}  // namespace slamcmp
