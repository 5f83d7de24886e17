#pragma once
// The chessboard's inner corners in every frame: the previous frame's corners tracked by pyramidal
// Lucas-Kanade and confirmed (sub-pixel re-refinement, a homography consistent with the grid on
// the undistorted corners, the square colours), with core's full search as the fallback. A full
// search costs 100 to 200 ms on a frame without the board, tracking well under a millisecond.
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/chessboard.h"
#include "core/target.h"

namespace slamcmp {

struct BoardCornerTrackerOptions {
  // The sub-pixel window as wide as the thesis allows (under half a square): on tv1..tv4 it cuts
  // the board pose error by 5 to 8 % against core's default of 0.4.
  ChessboardDetectorOptions detector = [] {
    ChessboardDetectorOptions d;
    d.refine_window_fraction = 0.49;
    return d;
  }();
  bool track = true;                   // track last frame's corners before any full search
  double max_grid_error_px = 1.0;      // confirm: RMS homography error of the undistorted corners
  double max_refine_shift_px = 2.0;    // confirm: sub-pixel refinement moves no corner further
  int search_interval_when_lost = 3;   // after a miss, full search only every this many frames
  double search_margin_px = 20;        // full search only if the last pose puts the board this far inside
  template <class V>
  void visit(V& v) {
    v("detector", detector, "the full search (core chessboard detector)");
    v("track", track, "track last frame's corners by Lucas-Kanade before any full search");
    v("max_grid_error_px", max_grid_error_px,
      "tracked corners are accepted when a homography fits the undistorted grid to this RMS, pixels");
    v("max_refine_shift_px", max_refine_shift_px,
      "tracked corners are rejected when sub-pixel refinement moves one further than this, pixels");
    v("search_interval_when_lost", search_interval_when_lost,
      "while the board is not seen, the full search runs every this many frames (1 = every frame)");
    v("search_margin_px", search_margin_px,
      "the full search is skipped while the last pose puts an outer corner of the board closer than this "
      "to the image border, pixels (a search on a frame with part of the board costs up to seconds)");
  }
  void check() const;
};

class BoardCornerTracker {
 public:
  BoardCornerTracker(const ChessboardTarget& target, const BoardCornerTrackerOptions& options);

  // Corners (distorted pixels, SPEC section 2 order) in the current frame, or empty. With a
  // camera and the previous frame's pyramid the corners are tracked first. `pyramid_*` come from
  // cv::buildOpticalFlowPyramid with the given window and levels.
  // allow_search = false skips the full search (e.g. the pose says the board is out of view).
  // A symmetric board found by the full search takes the origin nearest where T_world_camera_last
  // (the last posed frame's) puts its corners, else nearest the last corners seen
  // (chooseSymmetricOrder); tracked corners keep their order.
  std::optional<std::vector<cv::Point2f>> find(const cv::Mat& grey, const std::vector<cv::Mat>& pyramid_prev,
                                               const std::vector<cv::Mat>& pyramid, cv::Size lk_window,
                                               int lk_levels, const CameraModel* camera, bool allow_search = true,
                                               const SE3* T_world_camera_last = nullptr);
  bool lastWasTracked() const { return last_tracked_; }
  // Forget the last corners (the next call searches).
  void reset() { corners_.clear(); }

 private:
  bool confirm(const cv::Mat& grey, std::vector<cv::Point2f>& uv, const CameraModel& camera) const;

  ChessboardTarget target_;
  BoardCornerTrackerOptions options_;
  std::vector<cv::Point2f> corners_;  // last frame's, empty if not seen
  std::vector<cv::Point2f> last_seen_;  // the last corners found in any frame, empty if none yet
  int frames_until_search_ = 0;  // frames to skip before the next full search
  bool last_tracked_ = false;
};

}  // namespace slamcmp
