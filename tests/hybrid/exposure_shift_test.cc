// The shift a motion-blurred frame's corners share (hybrid/exposure_shift.h): an edge's spread
// against analytic blurs, and the exposure and the shift's covariance recovered from a board
// rendered over a known exposure while it accelerates.
#include "hybrid/exposure_shift.h"

#include <cmath>

#include <gtest/gtest.h>

#include "hybrid/edge_width.h"

namespace slamcmp {
namespace {

// A step of 150 grey levels across the line n . (p - p0) = 0 through the optics' Gaussian blur
// (sigma), smeared by a box of length L along n (the average of 64 Gaussian steps over it).
cv::Mat stepImage(const Vec2& p0, const Vec2& n, double sigma, double L) {
  cv::Mat grey(80, 80, CV_8UC1);
  for (int v = 0; v < grey.rows; ++v)
    for (int u = 0; u < grey.cols; ++u) {
      double sum = 0;
      for (int k = 0; k < 64; ++k) {
        const double d = n.dot(Vec2(u, v) - p0) - L * ((k + 0.5) / 64 - 0.5);
        sum += 0.5 * std::erfc(-d / (sigma * std::sqrt(2.0)));
      }
      grey.at<unsigned char>(v, u) = cv::saturate_cast<unsigned char>(50 + 150 * sum / 64);
    }
  return grey;
}

// The optics' blur spreads the derivative by sigma^2, and the bilinear samples by 1/6 more (their
// triangle's variance); a box of L pixels across the edge by L^2 / 12 more, along an axis or a
// diagonal.
TEST(EdgeSpread, GrowsByTheSquareOfTheStreakOverTwelve) {
  for (const Vec2& n : {Vec2(1, 0), Vec2(std::sqrt(0.5), std::sqrt(0.5))}) {
    const Vec2 p0(40.3, 39.6);
    const auto sharp = edgeSpread(stepImage(p0, n, 0.7, 0), p0, n, 8);
    ASSERT_TRUE(sharp);
    EXPECT_NEAR(*sharp, 0.49 + 1.0 / 6, 0.03);
    for (const double L : {2.0, 4.0, 6.0}) {
      const auto smeared = edgeSpread(stepImage(p0, n, 0.7, L), p0, n, 8);
      ASSERT_TRUE(smeared);
      EXPECT_NEAR(*smeared - *sharp, L * L / 12, 0.08 * L * L / 12 + 0.02) << "L " << L;
    }
  }
  // No step: nothing to measure.
  EXPECT_FALSE(edgeSpread(cv::Mat(80, 80, CV_8UC1, cv::Scalar(120)), Vec2(40, 40), Vec2(1, 0), 8));
  // A profile leaving the image: nothing either.
  EXPECT_FALSE(edgeSpread(stepImage(Vec2(3, 40), Vec2(1, 0), 0.7, 0), Vec2(3, 40), Vec2(1, 0), 8));
}

// A chessboard of 7 x 5 inner corners, 24 px squares, its top-left inner corner at `origin`,
// rendered as the mean over the exposure (16 instants, each through a 0.7 px blur) while it moves
// at `velocity` pixels a frame and accelerates at `accel` pixels a frame^2; t in frames.
struct MovingBoard {
  static constexpr int kCols = 7, kRows = 5;
  static constexpr double kSquare = 24;
  Vec2 origin0{40, 40}, velocity{3.0, 1.2}, accel{0.3, -0.2};
  Vec2 originAt(double t) const { return origin0 + velocity * t + 0.5 * accel * t * t; }
  static double level(const Vec2& p, const Vec2& origin) {
    // A smooth chessboard: the product of two smoothed square waves, their steps 0.7 px wide.
    const auto wave = [](double x) { return std::tanh(std::sin(M_PI * x / kSquare) * kSquare / (M_PI * 0.7 * 1.6)); };
    return 125 + 100 * wave(p.x() - origin.x()) * wave(p.y() - origin.y());
  }
  cv::Mat frame(double t, double exposure) const {
    cv::Mat grey(260, 320, CV_8UC1);
    for (int v = 0; v < grey.rows; ++v)
      for (int u = 0; u < grey.cols; ++u) {
        double sum = 0;
        for (int k = 0; k < 16; ++k) sum += level(Vec2(u, v), originAt(t + exposure * ((k + 0.5) / 16 - 0.5)));
        grey.at<unsigned char>(v, u) = cv::saturate_cast<unsigned char>(sum / 16);
      }
    return grey;
  }
  void corners(double t, std::vector<int>* ids, std::vector<cv::Point2f>* uv) const {
    ids->clear();
    uv->clear();
    const Vec2 o = originAt(t);
    for (int j = 0; j < kRows; ++j)
      for (int i = 0; i < kCols; ++i) {
        ids->push_back(j * kCols + i);
        uv->emplace_back(static_cast<float>(o.x() + i * kSquare), static_cast<float>(o.y() + j * kSquare));
      }
  }
  // Frames t = 0..frames-1 (at 10 Hz; `jitter` frames early or late, alternately) into `shift`.
  void feed(ExposureShift& shift, int frames, double exposure, double jitter = 0) const {
    std::vector<int> ids;
    std::vector<cv::Point2f> uv;
    for (int k = 0; k < frames; ++k) {
      const double t = k + (k % 2 ? jitter : -jitter);
      corners(t, &ids, &uv);
      shift.addFrame(0.1 * t, frame(t, exposure), kCols, ids, uv);
    }
  }
};

TEST(ExposureShift, RecoversTheExposureAndTheShiftOfAnAcceleratingBoard) {
  const MovingBoard board;
  for (const double jitter : {0.0, 0.08})
    for (const double exposure : {0.0, 0.5, 0.9}) {
      ExposureShift shift{ExposureShiftOptions()};
      board.feed(shift, 8, exposure, jitter);
      // The fit's lower bound over six frames' edges, in frames (0.1 s): within 0.05 under e^2
      // and 0.02 over it (the edges' spread also varies by a hundredth of a pixel^2 with where
      // they fall between pixels); none without a blur. With steps of 0.084 and 0.116 s alternately
      // the exposure is the shutter's time all the same.
      const double e = shift.exposure() / 0.1;
      if (exposure == 0) {
        EXPECT_EQ(e, 0) << "jitter " << jitter;
      }
      EXPECT_GT(e * e, exposure * exposure - 0.05) << "exposure " << exposure << ", jitter " << jitter;
      EXPECT_LT(e * e, exposure * exposure + 0.02) << "exposure " << exposure << ", jitter " << jitter;
      // The shared shift's std: T^2 / 24 |a|, a = accel pixels a frame^2 = 100 accel pixels/s^2.
      if (jitter == 0) {
        const double expected = 0.01 * e * e / 24 * 100 * board.accel.norm();
        EXPECT_NEAR(std::sqrt(shift.covariance()(0, 0)), expected, 1e-6 + 0.01 * expected) << "exposure " << exposure;
        EXPECT_EQ(shift.covariance()(0, 1), 0);
      }
    }
}

// The shift is a frame's: none over a skipped frame, none without the board, none after a
// restart until three frames measured the corners again, and none at max_exposure 0.
TEST(ExposureShift, NeedsThreeFramesInARow) {
  const MovingBoard board;
  ExposureShift shift{ExposureShiftOptions()};
  EXPECT_EQ(shift.exposure(), 0.0);  // no shift until the edges show a blur
  board.feed(shift, 8, 0.9);
  ASSERT_GT(shift.exposure(), 0.08);
  ASSERT_FALSE(shift.covariance().isZero());
  std::vector<int> ids;
  std::vector<cv::Point2f> uv;
  const auto add = [&](int t, bool with_board) {
    board.corners(t, &ids, &uv);
    if (!with_board) ids.clear(), uv.clear();
    shift.addFrame(0.1 * t, board.frame(t, 0.9), MovingBoard::kCols, ids, uv);
  };
  add(9, true);  // frame 8 skipped
  EXPECT_TRUE(shift.covariance().isZero());
  add(10, false);  // no board
  EXPECT_TRUE(shift.covariance().isZero());
  add(11, true);
  add(12, true);
  EXPECT_TRUE(shift.covariance().isZero());  // frames 10-12: 10 had no board
  add(13, true);
  EXPECT_FALSE(shift.covariance().isZero());
  shift.forgetFrames();
  add(14, true);
  EXPECT_TRUE(shift.covariance().isZero());
  EXPECT_GT(shift.exposure(), 0.08);  // the fit is the camera's: kept

  ExposureShiftOptions off;
  off.max_exposure = 0;
  ExposureShift none(off);
  board.feed(none, 4, 0.9);
  EXPECT_TRUE(none.covariance().isZero());
}

}  // namespace
}  // namespace slamcmp
