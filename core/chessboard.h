#pragma once
// Chessboard corner detection with the board frame of SPEC section 2: corner 0 is always the same
// physical corner (next to a black corner square), X along `cols`, Z into the board, at any roll.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/subpixel_corner.h"
#include "core/target.h"

namespace slamcmp {

struct ChessboardDetectorOptions {
  bool fast_check = true;            // OpenCV's quick rejection of frames without a board
  double refine_window_fraction = 0.4;  // sub-pixel window side / square side in pixels (< 0.5)
  int max_refine_half_window = 11;   // pixels
  SubpixelCornerOptions subpixel;
  template <class V>
  void visit(V& v) {
    v("fast_check", fast_check, "reject board-less frames quickly (CALIB_CB_FAST_CHECK)");
    v("refine_window_fraction", refine_window_fraction,
      "sub-pixel window side as a fraction of the square side in pixels, under 0.5");
    v("max_refine_half_window", max_refine_half_window, "pixels");
    v("subpixel", subpixel, "the corners' sub-pixel refinement");
  }
  void check() const;
  void checkImage(cv::Size image) const;  // cv::cornerSubPix needs 2 * half window + 5 pixels
};

// Full search: finds, orders and refines the inner corners (distorted pixels, OpenCV row-major
// order: index j * cols + i). Returns false when the board is not found. A symmetric board's order
// follows chooseSymmetricOrder's convention (no reference).
bool detectChessboard(const cv::Mat& grey, const ChessboardTarget& target,
                      std::vector<cv::Point2f>* uv_distorted,
                      const ChessboardDetectorOptions& options = {});

// Puts corners (a cols x rows grid in any of the detector's orders) into SPEC section 2's order by
// the handedness of the grid in the image and the colour of the corner squares. Returns false if the
// square colours cannot be told apart (the grid is not a chessboard). A symmetric board
// (ChessboardTarget::symmetric) gets the handedness only: chooseSymmetricOrder picks its origin.
bool orderChessboardCorners(const cv::Mat& grey, const ChessboardTarget& target,
                            std::vector<cv::Point2f>& uv);

// A symmetric board looks the same after a 180 degree turn (a square one after any quarter turn),
// so its corners may be numbered from the origin of any of these turns. Renumbers `uv` (a
// handedness-correct order, as orderChessboardCorners leaves it) by the turn whose corners are
// nearest `reference` (least sum of squared distances): the same board's corners in the previous
// frame, or projected from the last pose, so the origin is kept by continuity. With an empty
// reference, by the convention: the turn whose corner 0 is nearest the image's top-left corner.
// An asymmetric board is left as it is.
void chooseSymmetricOrder(const ChessboardTarget& target, std::vector<cv::Point2f>& uv,
                          const std::vector<cv::Point2f>& reference = {});

// Every inner corner (distorted pixels, SPEC section 2 order) seen from T_world_camera, NaN for
// one behind the camera.
std::vector<cv::Point2f> projectEveryBoardCorner(const CameraModel& camera, const ChessboardTarget& target,
                                                 const SE3& T_world_camera);

// The board's inner corners (distorted pixels, SPEC section 2 order) seen from T_world_camera, e.g.
// the reference of chooseSymmetricOrder; empty if one is not in front of the camera.
std::vector<cv::Point2f> projectBoardCorners(const CameraModel& camera, const ChessboardTarget& target,
                                             const SE3& T_world_camera);

// Sub-pixel refinement with a window under half a square (estimated from the corner spacing);
// `camera`: the lens that took `grey` (refineCornersSubpixel).
void refineChessboardCorners(const cv::Mat& grey, const ChessboardTarget& target,
                             std::vector<cv::Point2f>& uv,
                             const ChessboardDetectorOptions& options = {}, const CameraModel* camera = nullptr);

// Smallest distance between neighbouring corners of the grid, in pixels.
double minCornerSpacing(const ChessboardTarget& target, const std::vector<cv::Point2f>& uv);

}  // namespace slamcmp
