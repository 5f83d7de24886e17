#pragma once
// Where the board is in the image while no camera pose says so (calibration and two_view modes
// with the board away): the homography from the board's plane to the image when it was last seen,
// carried from frame to frame by the homography of the tracked features. Exact while the camera
// only turns, approximate when it also moves (the features' dominant plane stands in for the
// board's): a place to look for the board and a reason not to search the whole image while the
// board is predicted out of it, never a pose.
#include <optional>
#include <unordered_map>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/geometry.h"

namespace slamcmp {

struct BoardImageMotionOptions {
  bool enabled = true;         // predict the board from the image's motion while no pose does
  int min_matches = 12;        // features tracked from the previous frame needed to carry it on
  double max_error_px = 2.0;   // RANSAC threshold of the frame-to-frame homography, pixels
  template <class V>
  void visit(V& v) {
    v("enabled", enabled,
      "calibration and two_view modes: while no pose predicts the board, carry its last view by the features' "
      "frame-to-frame homography and search only where it puts the board");
    v("min_matches", min_matches, "features tracked from the previous frame needed to carry the prediction on");
    v("max_error_px", max_error_px, "inlier threshold of the frame-to-frame homography, pixels");
  }
  void check() const;
};

class BoardImageMotion {
 public:
  BoardImageMotion(const BoardImageMotionOptions& options, double focal_px);

  // The board seen: its corners' world positions (on the plane z = 0) and their undistorted
  // normalised coordinates (at least 4).
  void seen(const std::vector<Vec3>& p_world, const std::vector<Vec2>& xy);
  // One frame on (every frame, the board seen or not): the features' undistorted normalised
  // coordinates by id in the previous frame and in this one. Too few tracked, or no homography:
  // the prediction is dropped.
  void advance(const std::unordered_map<int, Vec2>& xy_previous, const std::unordered_map<int, Vec2>& xy_current);
  void forget() { H_image_board_.reset(); }
  bool predicting() const { return H_image_board_.has_value(); }
  // Every corner (`corners_world`, SPEC section 2 order) where the prediction puts it, distorted
  // pixels, NaN beyond the plane's horizon; empty when not predicting.
  std::vector<cv::Point2f> corners(const CameraModel& camera, const std::vector<Vec3>& corners_world) const;

 private:
  BoardImageMotionOptions options_;
  double focal_px_;
  std::optional<Mat3> H_image_board_;  // board plane (x, y) metres -> undistorted normalised image
};

}  // namespace slamcmp
