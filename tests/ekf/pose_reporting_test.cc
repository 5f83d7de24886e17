// PoseReporting's lost frames (ekf/pose_reporting.h), on hand-fed measurement counts and NIS: the
// innovation jump against the run's own level (core/statistics.h's median), its warm-up, its
// history across anchors and restarts, and the weakly measured frames.
#include "ekf/pose_reporting.h"

#include <gtest/gtest.h>

namespace slamcmp {
namespace {

// A filter certain of its position (1 mm): only the measurements decide.
EkfState certainState() {
  EkfState state;
  Eigen::Matrix<double, 13, 13> P = Eigen::Matrix<double, 13, 13>::Identity() * 1e-6;
  state.reset(SE3(), P);
  return state;
}

constexpr int kDof = 12;  // six matches

// A frame with six matches whose NIS per dof is `level`.
std::string frame(PoseReporting& reporting, double level, bool anchored = false) {
  static const EkfState state = certainState();
  return reporting.weakness(6, level * kDof, kDof, anchored, state);
}

TEST(PoseReporting, InnovationJumpAgainstTheRunsOwnLevel) {
  PoseReporting reporting{ReportingOptions{}};  // max_innovation_jump 50, over the last 30 frames
  for (int i = 0; i < 10; ++i) EXPECT_EQ(frame(reporting, i % 2 ? 0.008 : 0.012), "") << i;
  EXPECT_EQ(frame(reporting, 0.45), "");  // 45 times the median (0.01): a hard frame, not a jump
  const std::string why = frame(reporting, 0.7);  // 58 times the median of eleven (0.012)
  EXPECT_NE(why.find("58 times the run's innovation level"), std::string::npos) << why;
  // Lost until something anchors the filter again, whatever the next frames measure.
  EXPECT_NE(frame(reporting, 0.01).find("not anchored since"), std::string::npos);
  // An anchor (hybrid: the board's corners) ends the loss and keeps the run's level: a jump is
  // caught at once, with no new warm-up.
  EXPECT_EQ(frame(reporting, 0.01, /*anchored=*/true), "");
  // A frame the board anchors is posed whatever its room features innovate.
  EXPECT_EQ(frame(reporting, 0.7, /*anchored=*/true), "");
  EXPECT_NE(frame(reporting, 0.7), "");
}

TEST(PoseReporting, InnovationJumpNeedsTenFramesOfHistory) {
  PoseReporting reporting{ReportingOptions{}};
  for (int i = 0; i < 9; ++i) EXPECT_EQ(frame(reporting, 0.01), "");
  EXPECT_EQ(frame(reporting, 1.0), "");  // the tenth frame: no level to hold it to yet
  // A restart forgets the run's level.
  reporting.reset();
  EXPECT_EQ(frame(reporting, 1.0), "");
  // Frames without matches say nothing of the level and do not count towards the ten.
  PoseReporting unmatched{ReportingOptions{}};
  const EkfState state = certainState();
  for (int i = 0; i < 10; ++i) {
    EXPECT_EQ(unmatched.weakness(6, 0, 0, false, state), "");
    EXPECT_EQ(frame(unmatched, 0.01), "");
  }
  EXPECT_NE(frame(unmatched, 1.0), "");
}

TEST(PoseReporting, InnovationJumpOffAndWindow) {
  ReportingOptions off;
  off.max_innovation_jump = 0;
  PoseReporting unchecked{off};
  for (int i = 0; i < 20; ++i) EXPECT_EQ(frame(unchecked, 0.01), "");
  EXPECT_EQ(frame(unchecked, 100.0), "");

  // The level is the median of the last innovation_window frames: a run whose innovations grew
  // slowly is held to its recent level, not its first.
  ReportingOptions recent;
  recent.innovation_window = 10;
  PoseReporting windowed{recent};
  for (int i = 0; i < 10; ++i) EXPECT_EQ(frame(windowed, 0.001), "");
  for (int i = 0; i < 8; ++i) EXPECT_EQ(frame(windowed, 0.02), "") << i;  // at most 20 times the median
  EXPECT_EQ(frame(windowed, 0.5), "");  // 25 times the last ten's median, 500 times the first 18's
}

TEST(PoseReporting, WeaklyMeasuredFramesRunning) {
  PoseReporting reporting{ReportingOptions{}};  // min_measured 4, max_weak_frames 3
  const EkfState state = certainState();
  EXPECT_EQ(reporting.weakness(3, 0, 0, false, state), "");
  EXPECT_EQ(reporting.weakness(3, 0, 0, false, state), "");
  EXPECT_EQ(reporting.weakness(3, 0, 0, false, state), "fewer than 4 measurements a frame for 3 frames");
}

// A frame that measured nothing (a blank frame, one spliced from elsewhere) is lost at once: its pose
// would be the motion model's alone. Only that frame: the next one measured is posed, as nothing
// moved the filter. An anchored frame (a start from the board) measures nothing else and is posed.
TEST(PoseReporting, AFrameThatMeasuredNothingIsLost) {
  PoseReporting reporting{ReportingOptions{}};
  const EkfState state = certainState();
  EXPECT_EQ(reporting.weakness(0, 0, 0, false, state), "nothing measured in this frame: the pose would be the motion model's");
  EXPECT_EQ(reporting.weakness(6, 0, 0, false, state), "");
  EXPECT_EQ(reporting.weakness(0, 0, 0, true, state), "");
  // Still a weak frame of those running: three weak ones in a row are lost until an anchor.
  EXPECT_NE(reporting.weakness(0, 0, 0, false, state), "");
  EXPECT_EQ(reporting.weakness(2, 0, 0, false, state), "");
  EXPECT_EQ(reporting.weakness(2, 0, 0, false, state), "fewer than 4 measurements a frame for 3 frames");
  EXPECT_NE(reporting.weakness(6, 0, 0, false, state).find("not anchored since"), std::string::npos);
}

}  // namespace
}  // namespace slamcmp
