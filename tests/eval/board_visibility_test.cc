// The scores by what the true camera sees of the board: hand-made frames with every figure
// computed by hand, and the corners in view of a known camera before a board, part of it and
// turned away.
#include "eval/metrics/board_visibility.h"

#include <cmath>

#include <gtest/gtest.h>

#include "core/error.h"

namespace slamcmp {
namespace {

// A board of 4 corners: 50 frames with it all in view (5 mm for the first 10, which the settled
// error leaves out; 1 mm for 10-19; 1.5 mm for 20-49, within 30 frames of the half board), two with
// half of it (3 mm), one with a quarter (9 mm, neither partial nor whole), ten without it, 0.1 m a
// frame (a gap: 4 mm in its first frame against 5 mm, a frame lost, 20 mm after 0.8 m against 8
// mm), two with three quarters (2 mm), then the whole board: 30 frames at 2 mm but frame 70 lost
// and frame 94 at 3 mm (the last of the return's 30), then 46 at 1 mm.
std::vector<BoardViewFrame> handMadeFrames() {
  std::vector<BoardViewFrame> frames;
  const auto add = [&](int corners, double step, std::optional<double> error_mm) {
    BoardViewFrame f;
    f.frame = static_cast<int>(frames.size());
    f.corners_in_view = corners;
    f.step_m = step;
    if (error_mm) f.error_m = *error_mm * 1e-3;
    frames.push_back(f);
  };
  for (int i = 0; i < 50; ++i) add(4, 0.01, i < 10 ? 5.0 : i < 20 ? 1.0 : 1.5);
  add(2, 0.01, 3.0), add(2, 0.01, 3.0);
  add(1, 0.01, 9.0);
  for (int k = 1; k <= 10; ++k) {
    std::optional<double> error = 1.0;
    if (k == 1) error = 4.0;
    if (k == 5) error.reset();
    if (k == 8) error = 20.0;
    add(0, 0.1, error);
  }
  add(3, 0.01, 2.0), add(3, 0.01, 2.0);
  for (int i = 65; i < 95; ++i) add(4, 0.01, i == 70 ? std::nullopt : std::optional<double>(i == 94 ? 3.0 : 2.0));
  for (int i = 0; i < 46; ++i) add(4, 0.01, 1.0);
  return frames;
}

TEST(BoardVisibility, ScoresHandComputed) {
  const std::vector<BoardViewFrame> frames = handMadeFrames();
  ASSERT_EQ(frames.size(), 141u);
  const BoardVisibilityScores s = scoreBoardVisibility(frames, 4);
  ASSERT_EQ(s.gaps.size(), 1u);
  EXPECT_EQ(s.gaps[0].first, 53);
  EXPECT_EQ(s.gaps[0].last, 62);
  EXPECT_EQ(s.gaps[0].lost, 1);
  EXPECT_NEAR(s.gaps[0].worst_over_allowance, 20.0 / 8.0, 1e-12);  // 0.8 m since the board: 8 mm allowed
  EXPECT_NEAR(s.gaps[0].worst_error_m, 0.020, 1e-15);
  ASSERT_TRUE(s.return_frame);
  EXPECT_EQ(*s.return_frame, 65);
  EXPECT_EQ(s.after_return_lost, 1);
  EXPECT_NEAR(s.after_return_rms, std::sqrt((28 * 4 + 9) / 29.0) * 1e-3, 1e-15);  // 65-94 but 70
  // Settled: frames 10-19 and 95-140 (the first 10 left out; the end of the run counts as in view).
  EXPECT_NEAR(s.settled_rms, 0.001, 1e-15);
  EXPECT_EQ(s.partial_frames, 4);
  EXPECT_NEAR(s.partial_rms, std::sqrt((9 + 9 + 4 + 4) / 4.0) * 1e-3, 1e-15);
  EXPECT_EQ(s.returning_partial_frames, 2);
  EXPECT_NEAR(s.returning_partial_rms, 0.002, 1e-15);
  EXPECT_EQ(s.whole_frames, 125);
  EXPECT_NEAR(s.whole_rms,
              std::sqrt((10 * 25 + 10 * 1 + 30 * 2.25 + 28 * 4 + 9 + 46 * 1) / 125.0) * 1e-3, 1e-15);
  const nlohmann::json j = boardVisibilityToJson(s);
  EXPECT_NEAR(j["after_return_over_settled"].get<double>(), s.after_return_rms / 0.001, 1e-12);
  EXPECT_EQ(j["gaps"][0]["lost"], 1);
  EXPECT_EQ(j["return_frame"], 65);
  EXPECT_EQ(j["after_return_lost"], 1);
}

// A gap none of whose frames was posed has no worst error: null, not a perfect 0.
TEST(BoardVisibility, GapWhollyLostHasNoWorstError) {
  std::vector<BoardViewFrame> frames;
  for (int i = 0; i < 50; ++i) {
    BoardViewFrame f;
    f.frame = i;
    f.corners_in_view = i >= 20 && i < 23 ? 0 : 4;
    if (f.corners_in_view > 0) f.error_m = 0.001;
    frames.push_back(f);
  }
  const BoardVisibilityScores s = scoreBoardVisibility(frames, 4);
  ASSERT_EQ(s.gaps.size(), 1u);
  EXPECT_EQ(s.gaps[0].lost, 3);
  EXPECT_TRUE(std::isnan(s.gaps[0].worst_over_allowance));
  EXPECT_TRUE(boardVisibilityToJson(s)["gaps"][0]["worst_over_allowance"].is_null());
  ASSERT_TRUE(s.return_frame);
  EXPECT_EQ(*s.return_frame, 23);
}

TEST(BoardVisibility, BoardAlwaysInViewHasNoGapNorReturn) {
  std::vector<BoardViewFrame> frames(40);
  for (BoardViewFrame& f : frames) f.corners_in_view = 54, f.error_m = 0.001;
  const BoardVisibilityScores s = scoreBoardVisibility(frames, 54);
  EXPECT_TRUE(s.gaps.empty());
  EXPECT_FALSE(s.return_frame);
  EXPECT_TRUE(std::isnan(s.after_return_rms));
  EXPECT_TRUE(std::isnan(s.partial_rms));
  EXPECT_NEAR(s.whole_rms, 0.001, 1e-15);
  const nlohmann::json j = boardVisibilityToJson(s);
  for (const char* key : {"return_frame", "after_return_lost", "after_return_rms", "after_return_over_settled",
                          "partial_rms", "partial_over_whole"})
    EXPECT_TRUE(j[key].is_null()) << key;
}

TEST(BoardVisibility, FramesBeforeTheBoardIsFirstSeenAreNoGap) {
  std::vector<BoardViewFrame> frames(5);
  for (BoardViewFrame& f : frames) f.error_m = 1.0;  // the camera not yet on the board
  frames.push_back({5, 4, 0, 0.001});
  const BoardVisibilityScores s = scoreBoardVisibility(frames, 4);
  EXPECT_TRUE(s.gaps.empty());
  EXPECT_FALSE(s.return_frame);
}

// A 9 x 6 board of 0.1 m squares 1 m in front of a 640 x 480 pinhole camera (f = 500 px): a
// square is 50 px. Over the board's middle all 54 corners are in view. Moved 3 cm to the left of
// its first column, column 6 is at u = 635, inside the 3 px margin (636.5), 7 at 685: 42; 3.6 cm
// to the left, column 6 is at 638, in the image but not 3 px inside: 36; turned around, none.
// At 100 frames a second, a frame the run did not pose does not take its neighbour's pose 10 ms
// away.
TEST(BoardVisibility, CornersInViewOfAKnownCamera) {
  CameraModel camera;
  camera.width = 640, camera.height = 480;
  camera.fx = camera.fy = 500, camera.cx = 320, camera.cy = 240;
  ChessboardTarget target;
  target.cols = 9, target.rows = 6, target.square_size = 0.1;
  const Trajectory groundtruth = {{0.00, SE3(Mat3::Identity(), Vec3(0.4, 0.25, -1))},
                                  {0.01, SE3(Mat3::Identity(), Vec3(-0.03, 0.25, -1))},
                                  {0.02, SE3(Mat3::Identity(), Vec3(-0.036, 0.25, -1))},
                                  {0.03, SE3::fromRotvec(Vec3(0, M_PI, 0), Vec3(-0.036, 0.25, -1))}};
  // Frame 0 posed 2 mm off, frame 1 not posed, frames 2 and 3 exact; frame 4 has no ground truth
  // within the 5 ms allowed.
  const Trajectory estimate = {{0.00, SE3(Mat3::Identity(), Vec3(0.402, 0.25, -1))}, groundtruth[2], groundtruth[3]};
  const std::vector<BoardViewFrame> frames =
      boardViewFrames({0.00, 0.01, 0.02, 0.03, 0.04}, groundtruth, estimate, camera, target, 0.005);
  ASSERT_EQ(frames.size(), 4u);
  EXPECT_EQ(frames[0].corners_in_view, 54);
  EXPECT_EQ(frames[1].corners_in_view, 42);
  EXPECT_EQ(frames[2].corners_in_view, 36);
  EXPECT_EQ(boardCornersInView(camera, target.cornersWorld(), groundtruth[2].T_world_camera, 0.0), 42);
  EXPECT_EQ(frames[3].corners_in_view, 0);
  EXPECT_EQ(frames[3].frame, 3);
  EXPECT_NEAR(frames[1].step_m, 0.43, 1e-12);
  EXPECT_NEAR(frames[3].step_m, 0.0, 1e-12);
  ASSERT_TRUE(frames[0].error_m);
  EXPECT_NEAR(*frames[0].error_m, 0.002, 1e-12);
  EXPECT_FALSE(frames[1].error_m);
  ASSERT_TRUE(frames[2].error_m);
  EXPECT_NEAR(*frames[2].error_m, 0.0, 1e-12);
  EXPECT_NEAR(gapAllowanceM(0.2), 0.005, 1e-15);
  EXPECT_NEAR(gapAllowanceM(0.9), 0.009, 1e-15);
  const Trajectory backwards = {groundtruth[1], groundtruth[0]};
  EXPECT_THROW(boardViewFrames({0.00}, backwards, estimate, camera, target, 0.005), InputError);
}

}  // namespace
}  // namespace slamcmp
