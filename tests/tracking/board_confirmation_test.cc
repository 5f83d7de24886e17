// tracking/board_corner_tracker's confirmation of tracked and predicted corners on boards drawn
// here (a pinhole camera without a lens, the board facing it, every corner's pixel known): a
// corner pulled off by something in front of the board, predicted too far from where it is, or
// too near the image's edge, is dropped and the rest kept with their ids; a prediction slipped by
// one square is refused; a symmetric board keeps the origin its prediction gives it, turned by
// 180 degrees or a quarter turn, in the search and then in tracking.
#include "tracking/board_corner_tracker.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <optional>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/video/tracking.hpp>

#include "core/chessboard.h"

namespace slamcmp {
namespace {

const cv::Size kWindow(9, 9);  // cslam's default Lucas-Kanade window and levels
constexpr int kLevels = 3;
constexpr int kWidth = 400, kHeight = 300;
// Every corner kept is within this of its drawn pixel: cv::cornerSubPix (the default refinement)
// puts the corners of these drawings 0.103 px off, the same for every corner (their sub-pixel
// phases are alike); a corner kept at a wrong place is a pixel off or more.
constexpr double kTolerancePx = 0.2;

CameraModel pinhole() {
  CameraModel camera;
  camera.width = kWidth;
  camera.height = kHeight;
  camera.fx = camera.fy = 300;
  camera.cx = (kWidth - 1) / 2.0;
  camera.cy = (kHeight - 1) / 2.0;
  return camera;  // no distortion: distorted and undistorted pixels are the same
}

// A board facing the camera: corner (i, j) (grid units, SPEC section 2) at origin + spacing * (i, j)
// pixels; its squares (the one at (i + 0.5, j + 0.5) black when i + j is even) framed by a white
// margin a square wide, on a grey wall.
struct DrawnBoard {
  ChessboardTarget target;
  cv::Point2d origin;  // corner 0's pixel
  double spacing;      // pixels per square

  cv::Point2f pixelOf(double i, double j) const {
    return cv::Point2f(static_cast<float>(origin.x + spacing * i), static_cast<float>(origin.y + spacing * j));
  }
  // Every corner's pixel, SPEC section 2 order.
  std::vector<cv::Point2f> corners() const {
    std::vector<cv::Point2f> uv;
    for (int j = 0; j < target.rows; ++j)
      for (int i = 0; i < target.cols; ++i) uv.push_back(pixelOf(i, j));
    return uv;
  }
  // Grey level of the board at grid coordinates (x, y).
  double greyAt(double x, double y) const {
    constexpr double kBlack = 30, kWhite = 220, kWall = 120;
    if (x < -2 || y < -2 || x >= target.cols + 1 || y >= target.rows + 1) return kWall;
    if (x < -1 || y < -1 || x >= target.cols || y >= target.rows) return kWhite;
    const int a = static_cast<int>(std::floor(x)), b = static_cast<int>(std::floor(y));
    return (a + b) % 2 == 0 ? kBlack : kWhite;
  }
  // The image, each pixel the mean of 4 x 4 samples (anti-aliased edges, as a camera's); `cover`
  // (if given) paints over the board: the grey level at a pixel position, or a negative number
  // where it leaves the board visible.
  cv::Mat image(const std::function<double(double, double)>& cover = nullptr) const {
    cv::Mat grey(kHeight, kWidth, CV_8U);
    for (int v = 0; v < kHeight; ++v)
      for (int u = 0; u < kWidth; ++u) {
        double sum = 0;
        for (int sy = 0; sy < 4; ++sy)
          for (int sx = 0; sx < 4; ++sx) {
            const double x = u - 0.375 + 0.25 * sx, y = v - 0.375 + 0.25 * sy;
            const double covered = cover ? cover(x, y) : -1;
            sum += covered >= 0 ? covered : greyAt((x - origin.x) / spacing, (y - origin.y) / spacing);
          }
        grey.at<uchar>(v, u) = cv::saturate_cast<uchar>(sum / 16);
      }
    return grey;
  }
};

std::vector<cv::Mat> pyramid(const cv::Mat& grey) {
  std::vector<cv::Mat> p;
  cv::buildOpticalFlowPyramid(grey, p, kWindow, kLevels);
  return p;
}

// The corners found at the `predicted` ones (every corner, NaN where not predicted) without a
// previous frame, so by confirming the prediction alone: no search is allowed.
std::optional<BoardCorners> confirmPrediction(const cv::Mat& grey, const ChessboardTarget& target,
                                              const std::vector<cv::Point2f>& predicted,
                                              const BoardCornerTrackerOptions& options = {}) {
  BoardCornerTracker tracker(target, options);
  const auto corners =
      tracker.findCorners(grey, {}, pyramid(grey), kWindow, kLevels, pinhole(), nullptr, false, &predicted);
  if (corners) {
    EXPECT_EQ(tracker.lastFound(), BoardFound::Predicted);
  }
  return corners;
}

// The ids of `corners` other than those in `missing`, and each corner where `truth` (SPEC section
// 2 order) puts it, within `tolerance_px`.
void expectCornersAt(const BoardCorners& corners, const std::vector<cv::Point2f>& truth, const std::vector<int>& missing,
                     double tolerance_px) {
  std::vector<int> expected_ids;
  for (int id = 0; id < static_cast<int>(truth.size()); ++id)
    if (std::find(missing.begin(), missing.end(), id) == missing.end()) expected_ids.push_back(id);
  EXPECT_EQ(corners.ids, expected_ids);
  ASSERT_EQ(corners.uv.size(), corners.ids.size());
  for (size_t k = 0; k < corners.ids.size(); ++k)
    EXPECT_LT(cv::norm(corners.uv[k] - truth[corners.ids[k]]), tolerance_px) << "corner " << corners.ids[k];
}

// A 9 x 6 board (not symmetric), 30 px squares, wholly in the image; drawn once for the suite.
class BoardConfirmation : public ::testing::Test {
 protected:
  static const DrawnBoard& board() {
    static const DrawnBoard b{ChessboardTarget{9, 6, 0.03}, cv::Point2d(80.3, 70.6), 30.0};
    return b;
  }
  static const cv::Mat& plain() {
    static const cv::Mat grey = board().image();
    return grey;
  }
};

// A dark blob (a disc a fifth of a square across) in front of the board, beside corner (4, 2)
// inside a white square: the corner's four squares still show their colours a third of a square
// out, but the sub-pixel refinement is pulled about a pixel off the corner. The homography of the
// grid misses it by more than max_corner_error_px (0.3 px) and it is dropped; the other 53 corners
// are kept with their ids, each within kTolerancePx of its pixel.
TEST_F(BoardConfirmation, CornerPulledOffByABlobIsDroppedTheOthersKept) {
  const DrawnBoard& b = board();
  const cv::Point2f blob = b.pixelOf(4 + 0.12, 2 - 0.12);
  const double radius = 0.1 * b.spacing;
  const cv::Mat grey = b.image([&](double x, double y) { return std::hypot(x - blob.x, y - blob.y) < radius ? 60 : -1; });
  const auto corners = confirmPrediction(grey, b.target, b.corners());
  ASSERT_TRUE(corners.has_value());
  expectCornersAt(*corners, b.corners(), {2 * 9 + 4}, kTolerancePx);
}

// One corner (3, 4) predicted 3.6 px from where it is, the others where they are: the refinement
// takes it further than max_refine_shift_px (2 px), so it was not where the prediction put it and
// is dropped; the other 53 are kept within kTolerancePx. With the limit at 5 px the same corner is kept,
// at its pixel: the limit, nothing else, dropped it.
TEST_F(BoardConfirmation, CornerRefinedFurtherThanTheLimitIsDropped) {
  const DrawnBoard& b = board();
  const int far = 4 * 9 + 3;
  std::vector<cv::Point2f> predicted = b.corners();
  predicted[far] += cv::Point2f(3.0F, -2.0F);
  const auto corners = confirmPrediction(plain(), b.target, predicted);
  ASSERT_TRUE(corners.has_value());
  expectCornersAt(*corners, b.corners(), {far}, kTolerancePx);

  BoardCornerTrackerOptions wide;
  wide.max_refine_shift_px = 5;
  const auto all = confirmPrediction(plain(), b.target, predicted, wide);
  ASSERT_TRUE(all.has_value());
  expectCornersAt(*all, b.corners(), {}, kTolerancePx);
}

// The corners predicted one whole square to the left of where they are (corner (i, j) at (i + 1,
// j)'s pixel; the last column's predictions, on the board's white margin, left out): a grid as
// consistent as the true one, every corner a real corner, but every square's colour swapped.
// Refused: nothing is kept at a wrong id. (Three checks refuse it, each alone: every corner's own
// squares, the squares' mean colours, and the board's edges, whose squares seem to go on.)
TEST_F(BoardConfirmation, PredictionSlippedByOneSquareIsRefused) {
  const DrawnBoard& b = board();
  std::vector<cv::Point2f> slipped(b.target.numCorners(), cv::Point2f(std::numeric_limits<float>::quiet_NaN(),
                                                                      std::numeric_limits<float>::quiet_NaN()));
  for (int j = 0; j < b.target.rows; ++j)
    for (int i = 0; i + 1 < b.target.cols; ++i) slipped[j * b.target.cols + i] = b.pixelOf(i + 1, j);
  EXPECT_FALSE(confirmPrediction(plain(), b.target, slipped).has_value());
}

// The board approaching fast: 30 px squares wholly in view, then 44 px squares (the next frame,
// every corner predicted where it is) with column 7 of 9 at 9 px from the right edge and column 8
// beyond it. Tracking keeps column 7 (its margin, from the last frame's 30 px squares: a 6 px
// half window and 2 px), but now its squares' samples (a third of a square out) and its
// refinement's window (10 px) leave the image: it is dropped. Columns 0 to 6 are kept with their
// ids, each within kTolerancePx. (Either check alone drops it: the samples reach further out than
// the window on any board not sheared nearly flat.)
TEST_F(BoardConfirmation, CornerWhoseSquaresLeaveTheImageIsDropped) {
  const DrawnBoard near{board().target, cv::Point2d(82.5, 40.3), 44.0};
  const cv::Mat grey = near.image();
  BoardCornerTrackerOptions options;
  options.predicted_search = false;  // tracked or nothing
  BoardCornerTracker tracker(near.target, options);
  const CameraModel camera = pinhole();
  const std::vector<cv::Mat> first = pyramid(plain());
  ASSERT_TRUE(tracker.findCorners(plain(), {}, first, kWindow, kLevels, camera, nullptr, true).has_value());
  const std::vector<cv::Point2f> predicted = near.corners();
  const auto corners =
      tracker.findCorners(grey, first, pyramid(grey), kWindow, kLevels, camera, nullptr, false, &predicted);
  ASSERT_TRUE(corners.has_value());
  EXPECT_EQ(tracker.lastFound(), BoardFound::Tracked);
  std::vector<int> missing;
  for (int j = 0; j < near.target.rows; ++j) missing.insert(missing.end(), {j * 9 + 7, j * 9 + 8});
  std::sort(missing.begin(), missing.end());
  expectCornersAt(*corners, predicted, missing, kTolerancePx);
}

// A symmetric board is found by the search of the region around its predicted corners and then
// tracked into the next frame (the same view); `turned(i, j)` is the drawn board's corner that the
// prediction numbers (i, j). The corners keep the prediction's numbering in both frames, each
// within kTolerancePx of its pixel.
void expectSearchedThenTrackedAsPredicted(const DrawnBoard& b, const std::function<cv::Point2i(int, int)>& turned) {
  const cv::Mat grey = b.image();
  const std::vector<cv::Point2f> drawn = b.corners();
  std::vector<cv::Point2f> truth(drawn.size());
  for (int j = 0; j < b.target.rows; ++j)
    for (int i = 0; i < b.target.cols; ++i) {
      const cv::Point2i at = turned(i, j);
      truth[j * b.target.cols + i] = drawn[at.y * b.target.cols + at.x];
    }
  // Predicted 20 px off (a pose's error): beyond the predicted search's alignment, so the region
  // around the prediction is searched (predicted_search off for certain).
  std::vector<cv::Point2f> predicted = truth;
  for (cv::Point2f& p : predicted) p += cv::Point2f(20, -15);
  BoardCornerTrackerOptions options;
  options.predicted_search = false;
  BoardCornerTracker tracker(b.target, options);
  const CameraModel camera = pinhole();
  const std::vector<cv::Mat> current = pyramid(grey);
  const auto searched = tracker.findCorners(grey, {}, current, kWindow, kLevels, camera, nullptr, true, &predicted);
  ASSERT_TRUE(searched.has_value());
  EXPECT_EQ(tracker.lastFound(), BoardFound::Searched);
  expectCornersAt(*searched, truth, {}, kTolerancePx);
  // The next frame: tracked and confirmed (no search allowed), the squares' colours checked with
  // the numbering the search chose.
  const auto tracked = tracker.findCorners(grey, current, current, kWindow, kLevels, camera, nullptr, false);
  ASSERT_TRUE(tracked.has_value());
  EXPECT_EQ(tracker.lastFound(), BoardFound::Tracked);
  expectCornersAt(*tracked, truth, {}, kTolerancePx);
}

// An 8 x 6 board (both counts even: a 180 degree turn maps it onto itself) predicted with its
// origin at the bottom right, where the detector's convention (corner 0 nearest the image's top
// left) would not put it: the search renumbers it to the prediction, and tracking keeps that.
TEST(BoardConfirmationSymmetric, BoardTurnedBy180DegreesKeepsThePredictedOrigin) {
  const DrawnBoard b{ChessboardTarget{8, 6, 0.03}, cv::Point2d(90.4, 75.7), 30.0};
  expectSearchedThenTrackedAsPredicted(b, [](int i, int j) { return cv::Point2i(7 - i, 5 - j); });
}

// A 7 x 7 board (square, both counts odd: any quarter turn maps it onto itself) predicted a
// quarter turn from the drawing's numbering: the square outside the predicted corner 0 is white,
// so the squares' colours are checked the other way round (parity) when the corners are tracked;
// the corners keep the predicted numbering in both frames.
TEST(BoardConfirmationSymmetric, SquareBoardAQuarterTurnRoundKeepsThePredictedOriginAndIsTracked) {
  const DrawnBoard b{ChessboardTarget{7, 7, 0.03}, cv::Point2d(110.4, 60.7), 28.0};
  expectSearchedThenTrackedAsPredicted(b, [](int i, int j) { return cv::Point2i(6 - j, i); });
}

}  // namespace
}  // namespace slamcmp
