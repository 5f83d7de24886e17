// `slamcmp run` with a symmetric board (8x6 inner corners: a 180 degree turn looks the same). The
// origin is chosen in the first frame and kept by continuity: on a rendered sequence whose camera
// rolls through 200 degrees every pose agrees with the ground truth after one fixed transform (the
// identity or the board's turn), with the board tracked and with it searched afresh in every frame;
// the phone video (no camera file) is self-calibrated and posed.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/imgcodecs.hpp>

#include "core/camera.h"
#include "core/target.h"
#include "core/trajectory.h"
#include "datasets/camera_motion.h"
#include "datasets/room_scene.h"
#include "datasets/scene_renderer.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

using test::TempDir;

constexpr int kFrames = 50;
constexpr double kFps = 10.0;
constexpr double kRollDegrees = 200.0;  // 4 degrees a frame
// Frames 25 to 30 are blank (a covered lens): both back-ends lose the camera and find the board
// again at 126 degrees of roll, where the convention alone would pick the other origin.
constexpr int kBlankFrom = 25, kBlankTo = 30;
bool blank(int frame) { return frame >= kBlankFrom && frame <= kBlankTo; }
const ChessboardTarget kBoard8x6{8, 6, 0.04};

Vec3 boardCentre() {
  return Vec3(0.5 * (kBoard8x6.cols - 1) * kBoard8x6.square_size, 0.5 * (kBoard8x6.rows - 1) * kBoard8x6.square_size,
              0.0);
}

// The camera 0.7 m from the board centre, swaying sideways and up while it rolls from 0 to
// kRollDegrees about its optical axis.
SE3 rollingCamera(double t) {
  const double s = t * kFps / (kFrames - 1);  // 0 to 1 over the sequence
  const Vec3 offset(0.08 * std::sin(2 * M_PI * s), 0.05 * std::sin(M_PI * s), -0.7 + 0.05 * s);
  return lookAt(boardCentre() + offset, boardCentre(), kRollDegrees * M_PI / 180.0 * s);
}

// The presets' room with an 8x6 board, rendered into a sequence folder (SPEC section 3).
std::string renderRollingSequence(const TempDir& dir) {
  const std::string out = dir.file("rolling_8x6");
  std::filesystem::create_directories(out + "/rgb");
  const CameraModel camera = syntheticCamera();
  Scene scene = buildRoomScene(1);
  scene.target = kBoard8x6;
  writeCameraYaml(out + "/camera.yaml", camera);
  writeTargetYaml(out + "/target.yaml", scene.target);
  const SceneRenderer renderer(camera, scene, 2);
  Trajectory groundtruth;
  std::string list;
  for (int i = 0; i < kFrames; ++i) {
    const double t = i / kFps;
    char name[32];
    std::snprintf(name, sizeof name, "rgb/%06d.png", i);
    const cv::Mat image = blank(i) ? cv::Mat(480, 640, CV_8UC1, cv::Scalar(40))
                                   : renderer.renderFrame(rollingCamera, t, 1 / kFps, FrameEffects{}, 1, i);
    EXPECT_TRUE(cv::imwrite(out + "/" + name, image));
    list += std::to_string(t) + " " + name + "\n";
    groundtruth.push_back({t, rollingCamera(t)});
  }
  test::writeText(out + "/rgb.txt", list);
  writeTumTrajectory(out + "/groundtruth.txt", groundtruth);
  return out;
}

class RollingSymmetricBoard : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    sequence_ = renderRollingSequence(*dir_);
  }
  static void TearDownTestSuite() { delete dir_; }

  struct Agreement {
    int posed = 0;              // frames that show the scene and got a pose
    bool turned = false;        // the fixed transform is the board's 180 degree turn, not the identity
    double max_rel_trans = 0;   // metres: T_0^-1 T_k against the ground truth's, over those frames
    double max_rel_rot_deg = 0;
    double max_abs_trans = 0;   // metres: T_k against the fixed transform times the ground truth
  };

  // Runs slamcmp and compares every posed frame but the blank ones with the ground truth.
  static Agreement run(const std::string& backend, const std::string& config_text = "",
                       const std::string& sequence = sequence_) {
    const std::string out = dir_->file(backend + std::to_string(++runs_));
    std::string args = "run --backend " + backend + " --sequence " + sequence + " --out " + out;
    if (!config_text.empty()) {
      test::writeText(out + ".yaml", config_text);
      args += " --config " + out + ".yaml";
    }
    const test::CommandResult result = test::runSlamcmp(args);
    EXPECT_EQ(result.exit_code, 0) << result.err;
    EXPECT_NE(result.err.find("target.yaml: the 8x6 board is symmetric"), std::string::npos) << result.err;
    const Trajectory estimate = readTrajectory(out + "/trajectory.txt", TrajectoryFormat::Tum);
    const Trajectory truth = readTrajectory(sequence_ + "/groundtruth.txt", TrajectoryFormat::Tum);
    std::map<long, SE3> truth_at;
    for (const auto& p : truth) truth_at[std::lround(p.timestamp * kFps)] = p.T_world_camera;
    Agreement a;
    if (estimate.empty()) return a;
    const SE3& T_est_0 = estimate.front().T_world_camera;
    const SE3& T_gt_0 = truth_at.at(std::lround(estimate.front().timestamp * kFps));
    // T_est = G T_gt for one G: the identity, or the turn about the board's centre.
    const SE3 turn(rotationFromRotvec(Vec3(0, 0, M_PI)), 2 * boardCentre());
    // (The first camera looks along the board's normal through its centre: only the rotation tells.)
    a.turned = rotationAngle((turn * T_gt_0).R().transpose() * T_est_0.R()) <
               rotationAngle(T_gt_0.R().transpose() * T_est_0.R());
    const SE3 G = a.turned ? turn : SE3();
    for (const auto& p : estimate) {
      const long frame = std::lround(p.timestamp * kFps);
      if (blank(frame)) continue;  // monoslam predicts a few frames before it gives up
      const SE3& T_gt = truth_at.at(frame);
      const SE3 rel_error = (T_gt_0.inverse() * T_gt).inverse() * (T_est_0.inverse() * p.T_world_camera);
      a.max_rel_trans = std::max(a.max_rel_trans, rel_error.t().norm());
      a.max_rel_rot_deg = std::max(a.max_rel_rot_deg, rotationAngle(rel_error.R()) * 180 / M_PI);
      a.max_abs_trans = std::max(a.max_abs_trans, (p.T_world_camera.t() - (G * T_gt).t()).norm());
      ++a.posed;
    }
    return a;
  }

  static TempDir* dir_;
  static std::string sequence_;
  static int runs_;
};
TempDir* RollingSymmetricBoard::dir_ = nullptr;
std::string RollingSymmetricBoard::sequence_;
int RollingSymmetricBoard::runs_ = 0;

// The board's corners followed by Lucas-Kanade keep the first frame's origin through the roll; after
// the blank frames the full search takes the origin nearest the last pose's.
TEST_F(RollingSymmetricBoard, CslamCombinedNeverFlips) {
  const Agreement a = run("cslam");
  EXPECT_EQ(a.posed, kFrames - (kBlankTo - kBlankFrom + 1));
  // The first frame is upright: the convention (origin nearest the image's top-left) is the truth's.
  EXPECT_FALSE(a.turned);
  EXPECT_LT(a.max_rel_trans, 0.002);
  EXPECT_LT(a.max_rel_rot_deg, 0.1);
  EXPECT_LT(a.max_abs_trans, 0.002);
}

// A full search in every frame: the origin is kept by continuity with the last pose alone.
TEST_F(RollingSymmetricBoard, CslamSearchingEveryFrameNeverFlips) {
  const Agreement a = run("cslam", "%YAML:1.0\ncslam:\n  board:\n    track: false\n");
  EXPECT_EQ(a.posed, kFrames - (kBlankTo - kBlankFrom + 1));
  EXPECT_FALSE(a.turned);
  EXPECT_LT(a.max_rel_trans, 0.002);
  EXPECT_LT(a.max_rel_rot_deg, 0.1);
}

// The EKF starts from the board by the same convention and restarts after the blank frames (lost
// after two unmeasured frames) with the origin nearest its last pose's, in the second frame of
// the board's return (the first gives the restart its motion). A flip would cost 0.18 m and 180
// degrees.
TEST_F(RollingSymmetricBoard, MonoslamRestartNeverFlips) {
  const Agreement a = run("monoslam", "%YAML:1.0\nmonoslam:\n  health:\n    max_frames_unmeasured: 2\n");
  EXPECT_EQ(a.posed, kFrames - (kBlankTo - kBlankFrom + 1) - 1);
  EXPECT_FALSE(a.turned);
  EXPECT_LT(a.max_abs_trans, 0.025);
  EXPECT_LT(a.max_rel_rot_deg, 2.0);
}

// hybrid without the camera file: it self-calibrates from the views of the first 24 frames (the
// 24th at 92 degrees of roll, past where the convention turns the origin), each view's origin kept
// by continuity with the last, and the filter starts nearest the last of their late poses.
TEST_F(RollingSymmetricBoard, HybridSelfCalibratedNeverFlips) {
  const std::string no_camera = dir_->file("rolling_8x6_no_camera");
  std::filesystem::create_directories(no_camera);
  for (const char* entry : {"rgb", "rgb.txt", "target.yaml", "groundtruth.txt"})
    std::filesystem::create_symlink(sequence_ + "/" + entry, no_camera + "/" + entry);
  // A roll about the line of sight keeps the board's normal within 7 degrees: allowed here.
  const Agreement a = run(
      "hybrid", "%YAML:1.0\nhybrid:\n  calibration:\n    min_view_spread_deg: 0\n    max_frames: 24\n", no_camera);
  std::printf("hybrid self-calibrated: %d posed, turned %d, %.4f m, %.3f deg\n", a.posed, a.turned, a.max_abs_trans,
              a.max_rel_rot_deg);
  EXPECT_GE(a.posed, kFrames - (kBlankTo - kBlankFrom + 1) - 1);
  EXPECT_FALSE(a.turned);
  EXPECT_LT(a.max_abs_trans, 0.01);
}

// The phone video with no camera file: self-calibration gathers 8 distinct board views, which this
// slow clip takes until frame 176; every frame from then on is posed, and the earlier frames that
// showed the whole board are posed late from their corners (measured: 227 of 241; the other 14
// show part of it, or blur it: 101). Every gathering frame is searched: with the board tracker's
// interval after a miss, 102, 103, 174 and 175, which show the whole board, were not (223 of 241).
// With the camera from `slamcmp calibrate`: calibrate_command_test.
TEST(PhoneVideo, CslamSelfCalibratesAndPosesTheFramesShowingTheBoard) {
  SLAMCMP_REQUIRE_SHARED(shared);
  TempDir dir;
  const test::CommandResult result = test::runSlamcmp("run --backend cslam --sequence " + shared +
                                                      "/video_chessboard/chessboard.avi --out " + dir.file("run"));
  ASSERT_EQ(result.exit_code, 0) << result.err;
  EXPECT_NE(result.err.find("video_chessboard/target.yaml: the 8x6 board is symmetric"), std::string::npos)
      << result.err;
  std::ifstream in(dir.file("run/summary.json"));
  const nlohmann::json summary = nlohmann::json::parse(in);
  EXPECT_EQ(summary["board_symmetric"], true);
  EXPECT_EQ(summary["frames"], 241);
  EXPECT_GE(summary["tracked"].get<int>(), 225);
  EXPECT_TRUE(summary["options"].contains("self_calibration"));
  // frames.csv: every frame posed from the board or (no board before calibrating) initialising.
  const std::vector<std::string> rows = test::readLines(dir.file("run/frames.csv"));
  ASSERT_EQ(rows.size(), 242u);
  for (size_t k = 1; k < rows.size(); ++k)
    EXPECT_TRUE(rows[k].find(",board,") != std::string::npos || rows[k].find(",initialising,") != std::string::npos)
        << rows[k];
  for (int frame : {102, 103, 174, 175})  // the whole board, each right after a frame without it
    EXPECT_EQ(rows[1 + frame].rfind(std::to_string(frame) + ",", 0), 0u) << rows[1 + frame];
  for (int frame : {102, 103, 174, 175}) EXPECT_NE(rows[1 + frame].find(",board,"), std::string::npos) << rows[1 + frame];
  // Calibrated on frame 101, which shows no board: the next frame, which shows all of it, is
  // searched too (the interval after a miss had skipped it: "no board yet").
  const test::CommandResult early = test::runSlamcmp(
      "run --backend cslam --sequence " + shared + "/video_chessboard/chessboard.avi --max-frames 104 --out " +
      dir.file("early") + " --set cslam.calibration.min_views=3 --set cslam.calibration.max_frames=102");
  ASSERT_EQ(early.exit_code, 0) << early.err;
  const std::vector<std::string> early_rows = test::readLines(dir.file("early/frames.csv"));
  ASSERT_EQ(early_rows.size(), 105u);
  EXPECT_NE(early_rows[1 + 101].find(",initialising,"), std::string::npos) << early_rows[1 + 101];  // waits for the board
  EXPECT_NE(early_rows[1 + 102].find(",board,"), std::string::npos) << early_rows[1 + 102];
  // The late poses and the live ones keep one origin: no jump between neighbouring frames (a
  // handheld phone at 24 fps; measured at most 2.2 degrees).
  const Trajectory trajectory = readTrajectory(dir.file("run/trajectory.txt"));
  for (size_t k = 1; k < trajectory.size(); ++k) {
    if (trajectory[k].timestamp - trajectory[k - 1].timestamp > 1.5 / 24) continue;
    const Mat3 R_step = trajectory[k - 1].T_world_camera.R().transpose() * trajectory[k].T_world_camera.R();
    EXPECT_LT(rotationAngle(R_step) * 180 / M_PI, 10.0) << "at " << trajectory[k].timestamp << " s";
  }
}

}  // namespace
}  // namespace slamcmp
