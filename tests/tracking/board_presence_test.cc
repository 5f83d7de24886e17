// tracking/board_presence: the ChESS response on drawn junctions (strong at an X-junction, weak on
// an edge, a shape's corner and a flat patch), and the presence test on rendered tv1 frames: the
// board's view passes, the textured wall of squares around it does not, nor a part of the board
// too small to be the whole of it.
#include "tracking/board_presence.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "core/chessboard.h"
#include "core/sequence.h"
#include "datasets/synth_sequence.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

constexpr int kBlack = 40, kWhite = 200;  // contrast 160

// A 41x41 image, grey level inside(x', y') ? white : black, with (x', y') the pixel's offset from
// the centre turned by 10 degrees (so no ring sample lies on a boundary), lightly blurred as a lens.
cv::Mat drawn(const std::function<bool(double, double)>& inside) {
  cv::Mat image(41, 41, CV_8UC1);
  const double c = std::cos(10 * M_PI / 180), s = std::sin(10 * M_PI / 180);
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) {
      const double dx = x - 20, dy = y - 20;
      image.at<uchar>(y, x) = inside(c * dx + s * dy, -s * dx + c * dy) ? kWhite : kBlack;
    }
  cv::GaussianBlur(image, image, cv::Size(5, 5), 0.7);
  return image;
}

// Measured at radius 5: X-junction 935 (5.8 times the contrast; ideally 8 times), edge -1415, a
// square's corner -172, flat 0.
TEST(ChessResponse, StrongAtAnXJunctionOnly) {
  constexpr double kContrast = kWhite - kBlack;
  const double x_junction = chessResponse(drawn([](double x, double y) { return x * y > 0; }), 20, 20, 5);
  const double edge = chessResponse(drawn([](double x, double) { return x > 0; }), 20, 20, 5);
  const double corner = chessResponse(drawn([](double x, double y) { return x > 0 && y > 0; }), 20, 20, 5);
  const double flat = chessResponse(drawn([](double, double) { return true; }), 20, 20, 5);
  EXPECT_GT(x_junction, 4 * kContrast);
  EXPECT_LT(edge, 0.5 * kContrast);
  EXPECT_LT(corner, 0.5 * kContrast);
  EXPECT_NEAR(flat, 0, 1e-9);
}

class BoardPresenceTv1 : public ::testing::Test {
 protected:
  // tv1's frames 0 and 5, and the board's corners found in frame 0 by the detector.
  static void SetUpTestSuite() {
    test::TempDir dir;
    SynthOptions options;
    options.preset = "tv1";
    options.frames = 6;
    writeSyntheticSequence(options, dir.file("tv1"));
    Sequence seq = openSequence(dir.file("tv1"));
    ASSERT_TRUE(seq.target);
    target_ = *seq.target;
    std::vector<cv::Mat> frames;
    for (Frame f; seq.frames->next(&f);) frames.push_back(f.grey);
    ASSERT_EQ(frames.size(), 6u);
    first_ = frames.front();
    last_ = frames.back();
    ASSERT_TRUE(detectChessboard(first_, target_, &corners_));
  }

  static BoardPresence learnt() {
    BoardPresence presence(BoardPresenceOptions{});
    presence.seen(first_, corners_, minCornerSpacing(target_, corners_));
    EXPECT_TRUE(presence.learnt());
    return presence;
  }
  static cv::Rect whole() { return cv::Rect(0, 0, first_.cols, first_.rows); }
  // The box of the board's corners in frame 0 grown by `margin` pixels.
  static cv::Rect boardBox(int margin) {
    return cv::boundingRect(corners_) + cv::Point(-margin, -margin) + cv::Size(2 * margin, 2 * margin);
  }

  static ChessboardTarget target_;
  static cv::Mat first_, last_;
  static std::vector<cv::Point2f> corners_;
};
ChessboardTarget BoardPresenceTv1::target_;
cv::Mat BoardPresenceTv1::first_;
cv::Mat BoardPresenceTv1::last_;
std::vector<cv::Point2f> BoardPresenceTv1::corners_;

TEST_F(BoardPresenceTv1, TheBoardPassesInItsViewAndAnother) {
  const BoardPresence presence = learnt();
  EXPECT_TRUE(presence.mayHoldBoard(first_, whole(), target_.numCorners()));
  EXPECT_TRUE(presence.mayHoldBoard(last_, whole(), target_.numCorners()));
  EXPECT_TRUE(presence.mayHoldBoard(first_, boardBox(10), target_.numCorners()));
}

// The wall around the board is a texture of squares, diamonds and discs: each side of the frame
// beyond the board's box (grown by a square) is too poor in X-junctions for a board.
TEST_F(BoardPresenceTv1, TheTexturedWallAroundTheBoardDoesNot) {
  const BoardPresence presence = learnt();
  const cv::Rect box = boardBox(static_cast<int>(minCornerSpacing(target_, corners_)));
  const cv::Rect sides[4] = {cv::Rect(0, 0, box.x, first_.rows), cv::Rect(box.br().x, 0, first_.cols - box.br().x, first_.rows),
                             cv::Rect(0, 0, first_.cols, box.y), cv::Rect(0, box.br().y, first_.cols, first_.rows - box.br().y)};
  for (const cv::Rect& side : sides) {
    ASSERT_GT(side.area(), 0);
    EXPECT_FALSE(presence.mayHoldBoard(first_, side, target_.numCorners())) << side;
  }
}

// The test counts X-junctions against the board's corner count (min_corner_fraction 0.6): the
// left two thirds of the board pass, its left third does not.
TEST_F(BoardPresenceTv1, CountsTheBoardsCorners) {
  const BoardPresence presence = learnt();
  const cv::Rect box = boardBox(3);
  const cv::Rect two_thirds(box.x, box.y, box.width * 2 / 3, box.height);
  const cv::Rect one_third(box.x, box.y, box.width / 3, box.height);
  EXPECT_TRUE(presence.mayHoldBoard(first_, two_thirds, target_.numCorners()));
  EXPECT_FALSE(presence.mayHoldBoard(first_, one_third, target_.numCorners()));
}

// Nothing learnt yet, or the test off: no region is ruled out.
TEST_F(BoardPresenceTv1, RulesNothingOutUntilTheBoardIsSeenOrWhenOff) {
  const cv::Rect corner(0, 0, 100, 100);
  BoardPresence fresh(BoardPresenceOptions{});
  EXPECT_FALSE(fresh.learnt());
  EXPECT_TRUE(fresh.mayHoldBoard(first_, corner, target_.numCorners()));
  BoardPresenceOptions off;
  off.enabled = false;
  BoardPresence disabled(off);
  disabled.seen(first_, corners_, minCornerSpacing(target_, corners_));
  EXPECT_TRUE(disabled.mayHoldBoard(first_, corner, target_.numCorners()));
  EXPECT_FALSE(learnt().mayHoldBoard(first_, corner, target_.numCorners()));
}

// The detector behind the test (as the back-ends search): a region is found in whole-image pixels
// as the detector finds it on the whole frame, a region the test rules out is not searched, and
// the board's next view is found.
TEST_F(BoardPresenceTv1, TheGatedDetectorFindsWhatTheDetectorFinds) {
  PresenceGatedDetector detector(target_, ChessboardDetectorOptions{}, BoardPresenceOptions{});
  std::vector<cv::Point2f> in_region;
  ASSERT_TRUE(detector.detect(first_, boardBox(60) & whole(), &in_region));
  ASSERT_EQ(in_region.size(), corners_.size());
  for (size_t k = 0; k < corners_.size(); ++k) EXPECT_LT(cv::norm(in_region[k] - corners_[k]), 0.05) << k;
  std::vector<cv::Point2f> none;
  EXPECT_FALSE(detector.detect(first_, cv::Rect(0, 0, boardBox(0).x, first_.rows), &none));
  std::vector<cv::Point2f> later;
  EXPECT_TRUE(detector.detect(last_, &later));
  EXPECT_EQ(later.size(), corners_.size());
}

}  // namespace
}  // namespace slamcmp
