// Where new features start: the strongest corner of a free box, and (board-free start) one without
// a look-alike near it when a box has one.
#include "ekf/corner_selection.h"

#include <cmath>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

namespace slamcmp {
namespace {

constexpr int kPatch = 11;
constexpr double kMinNcc = 0.8;  // ActiveSearchOptions::min_ncc

// A 7x5-square chessboard of `square` pixels, top-left at (x0, y0), on a mid-grey image, blurred
// as the renders' optics are.
cv::Mat chessboard(cv::Size size, int x0, int y0, int square) {
  cv::Mat grey(size, CV_8U, cv::Scalar(128));
  for (int r = 0; r < 5; ++r)
    for (int c = 0; c < 7; ++c)
      cv::rectangle(grey, cv::Rect(x0 + c * square, y0 + r * square, square, square),
                    cv::Scalar((r + c) % 2 ? 220 : 30), cv::FILLED);
  cv::GaussianBlur(grey, grey, cv::Size(0, 0), 0.7);
  return grey;
}

TEST(CornerSelection, AChessboardCornerHasLookAlikesASquareAway) {
  const int square = 30;
  const cv::Mat grey = chessboard(cv::Size(400, 300), 50, 50, square);
  const Vec2 inner(50 + 3 * square, 50 + 2 * square);  // an inner corner, its neighbours all around
  // The same corner repeats a square away diagonally (and two along a row): inside a square window
  // of half-side a little over a square.
  EXPECT_FALSE(hasNoLookAlike(grey, inner, kPatch, square + 2, kMinNcc));
  // Nearer than that only the corner's own peak correlates.
  EXPECT_TRUE(hasNoLookAlike(grey, inner, kPatch, square - 8, kMinNcc));
}

TEST(CornerSelection, ALoneCornerHasNone) {
  cv::Mat grey(300, 400, CV_8U, cv::Scalar(128));
  cv::rectangle(grey, cv::Rect(200, 150, 60, 40), cv::Scalar(30), cv::FILLED);
  cv::circle(grey, cv::Point(120, 80), 15, cv::Scalar(220), cv::FILLED);
  cv::GaussianBlur(grey, grey, cv::Size(0, 0), 0.7);
  // Its rectangle's other corners are the same edges turned: none correlates at min_ncc.
  EXPECT_TRUE(hasNoLookAlike(grey, Vec2(200, 150), kPatch, 100, kMinNcc));
  // Beside the border the window is cut short, the corner's own peak still found and passed over.
  cv::rectangle(grey, cv::Rect(8, 150, 40, 40), cv::Scalar(200), cv::FILLED);
  EXPECT_TRUE(hasNoLookAlike(grey, Vec2(8, 150), kPatch, 30, kMinNcc));
  // A patch that leaves the image has no template to look with.
  EXPECT_FALSE(hasNoLookAlike(grey, Vec2(3, 150), kPatch, 30, kMinNcc));
}

TEST(CornerSelection, TriesTheBoxsCornersInTurnAndFallsBackToTheStrongest) {
  const int square = 30;
  const cv::Mat grey = chessboard(cv::Size(640, 480), 120, 120, square);
  FeatureInitOptions options;
  options.box_width = 640 - 2 * 21;  // one box: the whole image within the margin
  options.box_height = 480 - 2 * 21;
  const auto strongest = [&](const std::function<bool(const Vec2&)>& preferred) {
    std::mt19937 rng(0);
    Vec2 uv;
    EXPECT_TRUE(findCornerInFreeBox(grey, {}, options, 21, rng, &uv, preferred));
    return uv;
  };
  const auto onTheGrid = [&](const Vec2& uv) {
    const double cx = (uv.x() - 120) / square, cy = (uv.y() - 120) / square;
    return std::abs(cx - std::round(cx)) * square <= 1.5 && std::abs(cy - std::round(cy)) * square <= 1.5;
  };
  const Vec2 first = strongest(nullptr);
  EXPECT_TRUE(onTheGrid(first));
  // The strongest refused: another of the board's corners, tried next.
  const Vec2 next = strongest([&](const Vec2& uv) { return (uv - first).norm() > 3; });
  EXPECT_GT((next - first).norm(), 3);
  EXPECT_TRUE(onTheGrid(next));
  // None preferred: the strongest all the same (a corner with look-alikes beats none)...
  const auto none = [](const Vec2&) { return false; };
  EXPECT_LT((strongest(none) - first).norm(), 1e-9);
  // ...that is usable: one that is not is passed over.
  std::mt19937 rng(0);
  Vec2 uv;
  ASSERT_TRUE(findCornerInFreeBox(grey, {}, options, 21, rng, &uv, none,
                                  [&](const Vec2& corner) { return (corner - first).norm() > 3; }));
  EXPECT_GT((uv - first).norm(), 3);
  EXPECT_TRUE(onTheGrid(uv));
}

}  // namespace
}  // namespace slamcmp
