// Drift over path segments as the KITTI odometry devkit computes it (evaluate_odometry.cpp).
#include "eval/metrics/segment_drift.h"

#include <cmath>

#include <gtest/gtest.h>

namespace slamcmp {
namespace {

// Poses every `step` metres along x, `n` of them.
std::vector<SE3> straightLine(int n, double step) {
  std::vector<SE3> T;
  for (int i = 0; i < n; ++i) T.push_back(SE3(Mat3::Identity(), Vec3(step * i, 0, 0)));
  return T;
}

TEST(SegmentDrift, LengthsAreTheDevkitsOnLongPathsAndTenthsOnShortOnes) {
  EXPECT_EQ(driftSegmentLengths(2000), (std::vector<double>{100, 200, 300, 400, 500, 600, 700, 800}));
  // KITTI's drive 04 is 394 m: the devkit's lengths still (only 100..300 m find segments); EuRoC's
  // MH_03 (131 m) would get 100 m segments from its first 31 m only: tenths.
  EXPECT_EQ(driftSegmentLengths(394), driftSegmentLengths(2000));
  EXPECT_NEAR(driftSegmentLengths(131).front(), 13.1, 1e-12);
  const std::vector<double> room = driftSegmentLengths(1.5);
  ASSERT_EQ(room.size(), 8u);
  for (int k = 0; k < 8; ++k) EXPECT_NEAR(room[k], 0.15 * (k + 1), 1e-12);
}

// A 1 % scale error: every segment's translation error is 1 % of its travelled length, which the
// devkit divides by the nominal length (the first pose strictly beyond it: length + 1 step here).
TEST(SegmentDrift, ScaleErrorOnAKittiLengthDrive) {
  const std::vector<SE3> gt = straightLine(1001, 1.0);  // 1000 m
  std::vector<SE3> est;
  for (const SE3& T : gt) est.push_back(SE3(Mat3::Identity(), 1.01 * T.t()));
  const auto drift = segmentDrift(gt, est, pathLength(gt));
  ASSERT_TRUE(drift);
  EXPECT_TRUE(drift->kitti_lengths);
  double sum = 0;
  int segments = 0;
  for (int len = 100; len <= 800; len += 100) {
    // Starts 0, 10, 20, ...: the segment's last pose first + len + 1 must exist (<= 1000).
    for (int first = 0; first + len + 1 <= 1000; first += 10) {
      sum += 0.01 * (len + 1) / len;
      ++segments;
    }
  }
  EXPECT_EQ(drift->segments, segments);
  EXPECT_NEAR(drift->trans_percent, 100.0 * sum / segments, 1e-9);
  EXPECT_NEAR(drift->rot_deg_per_m, 0.0, 1e-9);
  ASSERT_EQ(drift->lengths.size(), 8u);
  EXPECT_EQ(drift->lengths.front().segments, 90);  // first + 101 <= 1000: 0..890

  // A drive as short as KITTI's 03 and 04 (455 m): the devkit's lengths that fit, 100..400 m.
  const std::vector<SE3> short_gt = straightLine(456, 1.0);
  std::vector<SE3> short_est;
  for (const SE3& T : short_gt) short_est.push_back(SE3(Mat3::Identity(), 1.01 * T.t()));
  const auto short_drift = segmentDrift(short_gt, short_est, pathLength(short_gt));
  ASSERT_TRUE(short_drift);
  EXPECT_TRUE(short_drift->kitti_lengths);
  ASSERT_EQ(short_drift->lengths.size(), 4u);
  EXPECT_EQ(short_drift->lengths.back().length_m, 400.0);
  sum = 0;
  segments = 0;
  for (int len = 100; len <= 400; len += 100)
    for (int first = 0; first + len + 1 <= 455; first += 10) {
      sum += 0.01 * (len + 1) / len;
      ++segments;
    }
  EXPECT_EQ(short_drift->segments, segments);
  EXPECT_NEAR(short_drift->trans_percent, 100.0 * sum / segments, 1e-9);
}

// A yaw drift of 0.01 rad per metre: the rotation error of every segment is its length's worth.
TEST(SegmentDrift, YawDriftOnARoomScalePath) {
  const int n = 206;
  const double step = 0.01;  // 2.05 m: the tenths (20.5 steps) fall between poses, not on one
  const std::vector<SE3> gt = straightLine(n, step);
  std::vector<SE3> est;
  for (int i = 0; i < n; ++i) {
    const double yaw = 0.01 * step * i;
    Mat3 R;
    R << std::cos(yaw), -std::sin(yaw), 0, std::sin(yaw), std::cos(yaw), 0, 0, 0, 1;
    est.push_back(SE3(R, gt[i].t()));
  }
  const auto drift = segmentDrift(gt, est, pathLength(gt));
  ASSERT_TRUE(drift);
  EXPECT_FALSE(drift->kitti_lengths);
  EXPECT_NEAR(drift->path_m, 2.05, 1e-9);
  EXPECT_NEAR(drift->lengths.front().length_m, 0.205, 1e-9);
  // Each segment of nominal length L spans L + step (the first pose strictly beyond L): its angle is
  // 0.01 (L + step), over L.
  double expected = 0;
  int segments = 0;
  for (int k = 1; k <= 8; ++k) {
    const double len = 0.205 * k;
    for (int first = 0; first < n; first += 10) {
      int last = first;
      while (last < n && !(step * last > step * first + len)) ++last;
      if (last == n) continue;
      expected += 0.01 * step * (last - first) / len;
      ++segments;
    }
  }
  EXPECT_EQ(drift->segments, segments);
  EXPECT_NEAR(drift->rot_deg_per_m, expected / segments * 180.0 / M_PI, 1e-6);
}

TEST(SegmentDrift, NothingWithoutASegment) {
  const std::vector<SE3> gt = straightLine(5, 0.1);
  EXPECT_FALSE(segmentDrift(gt, gt, 0.0));
  EXPECT_FALSE(segmentDrift({gt[0]}, {gt[0]}, 1.0));
  // A path of 0.4 m whose matched poses cover only its first 0.05 m: no tenth fits.
  EXPECT_FALSE(segmentDrift({gt[0], SE3(Mat3::Identity(), Vec3(0.05, 0, 0))},
                            {gt[0], SE3(Mat3::Identity(), Vec3(0.05, 0, 0))}, 4.0));
}

// Found by the reliability probe: 2 poses 6 mm apart gave 167 % drift over tenths of 0.6 to 4.8
// mm, every segment the one motion between them. Poses further apart on average than the longest
// segment measure none, and say why.
TEST(SegmentDrift, NoneFromPosesFurtherApartThanTheLongestSegment) {
  const std::vector<SE3> gt = straightLine(2, 0.006);
  const std::vector<SE3> est{gt[0], SE3(Mat3::Identity(), Vec3(0.005, 0.001, 0))};
  std::string why;
  EXPECT_FALSE(segmentDrift(gt, est, 0.006, &why));
  EXPECT_EQ(why, "the 2 matched poses are 0.006 m apart on average, more than the longest segment (0.0048 m): "
                 "too few to measure drift over segments");
  // A third pose halfway is enough: segments end at different poses.
  EXPECT_TRUE(segmentDrift(straightLine(3, 0.003), straightLine(3, 0.003), 0.006, &why));
  // The devkit's lengths: 2 poses 1 km apart, against at most 800 m.
  EXPECT_FALSE(segmentDrift(straightLine(2, 1000), straightLine(2, 1000), 1000, &why));
  EXPECT_NE(why.find("too few to measure drift"), std::string::npos) << why;
}

}  // namespace
}  // namespace slamcmp
