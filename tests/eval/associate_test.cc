// Timestamp association as evo's sync.associate_trajectories does it.
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/error.h"
#include "eval/metrics/associate.h"

namespace slamcmp {
namespace {

Trajectory atTimes(const std::vector<double>& times) {
  Trajectory t;
  for (double time : times) t.push_back({time, SE3()});
  return t;
}

TEST(Associate, JitteredTimestampsPairWithTheirPoses) {
  std::vector<double> t_gt, t_est;
  const double jitter[] = {0.004, -0.003, 0.0, 0.0099, -0.0099, 0.001};
  for (int i = 0; i < 6; ++i) {
    t_gt.push_back(100.0 + 0.1 * i);
    t_est.push_back(100.0 + 0.1 * i + jitter[i]);
  }
  const PosePairs pairs = associateByTime(atTimes(t_gt), atTimes(t_est), 0.01);
  ASSERT_EQ(pairs.size(), 6u);
  for (size_t k = 0; k < 6; ++k) {
    EXPECT_EQ(pairs.groundtruth[k], k);
    EXPECT_EQ(pairs.estimate[k], k);
  }
}

TEST(Associate, PosesBeyondMaxDiffAreDropped) {
  const Trajectory gt = atTimes({0.0, 1.0, 2.0, 3.0});
  const Trajectory est = atTimes({0.005, 1.02, 2.0, 2.95});
  const PosePairs pairs = associateByTime(gt, est, 0.01);
  EXPECT_EQ(pairs.groundtruth, (std::vector<size_t>{0, 2}));
  EXPECT_EQ(pairs.estimate, (std::vector<size_t>{0, 2}));
  EXPECT_EQ(associateByTime(gt, est, 0.05).size(), 4u);
}

// evo adds its offset_2 to the longer trajectory's times (subtracts it from the ground truth's
// when that is the longer), and a pair exactly max_diff apart is kept or dropped by that rounding:
// here evo_ape keeps the first two pairs. Adding the offset to the (shorter) estimate instead
// kept only the fourth.
TEST(Associate, AnOffsetIsAppliedAsEvoAppliesIt) {
  const Trajectory gt = atTimes({1.011, 1.111, 1.211, 1.311, 1.411, 1.511});
  const Trajectory est = atTimes({1.637, 1.737, 1.837, 1.937, 2.037});
  PosePairs pairs = associateByTime(gt, est, 0.01, -0.636);
  EXPECT_EQ(pairs.groundtruth, (std::vector<size_t>{0, 1}));
  EXPECT_EQ(pairs.estimate, (std::vector<size_t>{0, 1}));
  // The estimate longer: the offset moves the estimate's times.
  pairs = associateByTime(atTimes({0.0, 1.0}), atTimes({0.3, 0.5, 1.3, 1.5}), 0.01, -0.3);
  EXPECT_EQ(pairs.groundtruth, (std::vector<size_t>{0, 1}));
  EXPECT_EQ(pairs.estimate, (std::vector<size_t>{0, 2}));
}

// evo takes the shorter trajectory's poses one by one (the estimate's on equal length) and the
// nearest pose of the longer one; the earlier of two equally near, and the same pose twice if
// it is the nearest twice.
TEST(Associate, ShorterTrajectoryIsSearchedInTheLonger) {
  // Estimate longer: each ground-truth pose picks its nearest estimate pose.
  PosePairs pairs =
      associateByTime(atTimes({0.0, 1.0}), atTimes({0.0, 0.004, 0.5, 1.003, 2.0}), 0.01);
  EXPECT_EQ(pairs.groundtruth, (std::vector<size_t>{0, 1}));
  EXPECT_EQ(pairs.estimate, (std::vector<size_t>{0, 3}));

  // Estimate shorter: both estimate poses are nearest to ground-truth pose 0.
  pairs = associateByTime(atTimes({0.0, 10.0, 20.0}), atTimes({0.001, 0.002}), 0.01);
  EXPECT_EQ(pairs.groundtruth, (std::vector<size_t>{0, 0}));
  EXPECT_EQ(pairs.estimate, (std::vector<size_t>{0, 1}));

  // A tie goes to the earlier pose.
  pairs = associateByTime(atTimes({0.0, 1.0, 2.0}), atTimes({0.5, 1.5}), 0.5);
  EXPECT_EQ(pairs.groundtruth, (std::vector<size_t>{0, 1}));
}

TEST(Associate, NothingMatchedSaysWhy) {
  // The commonest mistake: nanoseconds against seconds.
  const Trajectory gt = atTimes({1305031102.1, 1305031102.2, 1305031102.3});
  const Trajectory est = atTimes({1305031102.1e9, 1305031102.2e9});
  try {
    associateByTime(gt, est, 0.01);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("time units differ"), std::string::npos) << what;
    EXPECT_NE(what.find("1e+09 times"), std::string::npos) << what;  // the factor
    EXPECT_NE(what.find("ns against s"), std::string::npos) << what;
    EXPECT_NE(what.find("1305031102.1 .. 1305031102.3"), std::string::npos)
        << what;  // the time ranges
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

// Relative times in ms against s overlap near 0 and pair a pose or two by chance: still reported
// as the unit mismatch it is, with the factor, not as too few pairs.
TEST(Associate, MillisecondsAgainstSecondsAreNamedEvenWithAChancePair) {
  std::vector<double> t_gt, t_est;
  for (int i = 0; i < 50; ++i) {
    t_gt.push_back(0.1 * i);
    t_est.push_back(100.0 * i);  // the same frames in ms
  }
  try {
    associateByTime(atTimes(t_gt), atTimes(t_est), 0.01);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("estimate's timestamps are 1000 times the ground truth's"), std::string::npos) << what;
    EXPECT_NE(what.find("ms against s"), std::string::npos) << what;
  }
  // The other way round: the ground truth in ms.
  try {
    associateByTime(atTimes(t_est), atTimes(t_gt), 0.01);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("ground truth's timestamps are 1000 times the estimate's"), std::string::npos)
        << e.what();
  }
}

TEST(Associate, NoOverlapSaysByHowMuch) {
  try {
    associateByTime(atTimes({10.0, 10.1, 10.2, 10.3}), atTimes({12.3, 12.4, 12.5}), 0.01);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("no time overlap"), std::string::npos) << what;
    EXPECT_NE(what.find("starts 2 s after the ground truth ends"), std::string::npos) << what;
  }
}

// A short estimate inside a long ground truth is not a unit mismatch.
TEST(Associate, AShortEstimateInsideIsFine) {
  std::vector<double> t_gt;
  for (int i = 0; i < 1000; ++i) t_gt.push_back(1305031102.0 + 0.1 * i);
  EXPECT_EQ(associateByTime(atTimes(t_gt), atTimes({1305031102.5, 1305031102.6}), 0.01).size(), 2u);
}

// Published ground truth repeats a timestamp now and then (TUM fr2_desk): evo's argmin takes the
// first of the equally near poses.
TEST(Associate, RepeatedTimestampsTakeTheFirst) {
  PosePairs pairs = associateByTime(atTimes({0.0, 1.0, 1.0, 2.0}), atTimes({1.004}), 0.01);
  EXPECT_EQ(pairs.groundtruth, (std::vector<size_t>{1}));
  pairs = associateByTime(atTimes({0.997}), atTimes({0.0, 1.0, 1.0, 2.0}), 0.01);
  EXPECT_EQ(pairs.estimate, (std::vector<size_t>{1}));
}

TEST(Associate, DecreasingTimestampsAreRefused) {
  EXPECT_THROW(associateByTime(atTimes({0.0, 2.0, 1.0}), atTimes({0.0}), 0.01), InputError);
}

}  // namespace
}  // namespace slamcmp
