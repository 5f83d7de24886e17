// `slamcmp calibrate` on the published calibration image sets (issue 3 targets).
#include <fstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "core/camera.h"
#include "core/target.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

int runCalibrate(const std::string& sequence, const ChessboardTarget& target, const test::TempDir& dir,
                 const std::string& extra = "") {
  writeTargetYaml(dir.file("target.yaml"), target);
  return test::runSlamcmp("calibrate --sequence " + sequence + " --target " + dir.file("target.yaml") +
                          " --out " + dir.file("camera.yaml") + extra)
      .exit_code;
}

// Bouguet's toolbox example (13x12 inner corners, 30 mm): within 0.5 % of the published focal
// lengths and 2 px of the principal point (measured: 0.3 %, 1.4 px).
TEST(CalibrateCommand, BouguetMatchesThePublishedResult) {
  SLAMCMP_REQUIRE_SHARED(shared);
  test::TempDir dir;
  ASSERT_EQ(runCalibrate(shared + "/calibration/bouguet", {13, 12, 0.03}, dir), 0);
  const CameraModel c = readCameraYaml(dir.file("camera.yaml"));
  EXPECT_NEAR(c.fx, 657.463, 0.005 * 657.463);
  EXPECT_NEAR(c.fy, 657.947, 0.005 * 657.947);
  EXPECT_NEAR(c.cx, 303.137, 2.0);
  EXPECT_NEAR(c.cy, 242.569, 2.0);
}

// The same with the corners by gradient orthogonality (core/subpixel_corner.h): within 0.2 % and
// 1.5 px (measured: fx, fy 0.02 % and 0.08 % off, the principal point 0.8 px; with cv::cornerSubPix
// 0.27 % and 0.36 %, 1.4 px).
TEST(CalibrateCommand, BouguetWithGradientCornersIsCloserStill) {
  SLAMCMP_REQUIRE_SHARED(shared);
  test::TempDir dir;
  ASSERT_EQ(runCalibrate(shared + "/calibration/bouguet", {13, 12, 0.03}, dir, " --subpixel gradient"), 0);
  const CameraModel c = readCameraYaml(dir.file("camera.yaml"));
  EXPECT_NEAR(c.fx, 657.463, 0.002 * 657.463);
  EXPECT_NEAR(c.fy, 657.947, 0.002 * 657.947);
  EXPECT_NEAR(c.cx, 303.137, 1.5);
  EXPECT_NEAR(c.cy, 242.569, 1.5);
}

// OpenCV's left camera sample (9x6, 25 mm). The published calibration (fx = fy = 535.9, fixed
// aspect ratio, 11x11 sub-pixel windows, rms 0.39 px) and ours (windows under half a square, rms
// 0.20 px) differ by 0.6 % in focal length: the tolerance is 1 %, and 2 px for the principal point.
// The published value is the biased one: this board's bottom row of squares is cut short, and the
// 23x23-pixel windows reach the cut and pull the corners next to it by up to 6 px (left02: view
// error 1.18 px). OpenCV's sample re-run here gives the published figures to 0.01 px; with half-
// windows of 3 to 9 px instead of 11 it gives fx 532.2 to 533.1, as ours. On rendered views of such
// a board (self_calibration_test.cc) ours recovers fx to 0.01 %; 11x11 windows miss it by 2.4 %.
TEST(CalibrateCommand, OpencvLeftMatchesThePublishedResult) {
  SLAMCMP_REQUIRE_SHARED(shared);
  test::TempDir dir;
  ASSERT_EQ(runCalibrate(shared + "/calibration/opencv_left", {9, 6, 0.025}, dir), 0);
  const CameraModel c = readCameraYaml(dir.file("camera.yaml"));
  EXPECT_NEAR(c.fx, 535.916, 0.01 * 535.916);
  EXPECT_NEAR(c.fy, 535.916, 0.01 * 535.916);
  EXPECT_NEAR(c.cx, 342.283, 2.0);
  EXPECT_NEAR(c.cy, 235.571, 2.0);
}

// The wrong board size (a 7x4 part of the 9x6 board is found, but the views do not fit one camera):
// exit 2 with a message, no camera.yaml.
TEST(CalibrateCommand, NoBoardIsBadInput) {
  SLAMCMP_REQUIRE_SHARED(shared);
  test::TempDir dir;
  EXPECT_EQ(runCalibrate(shared + "/calibration/opencv_left", {7, 4, 0.025}, dir), 2);
  EXPECT_FALSE(std::ifstream(dir.file("camera.yaml")).good());
}

// --out names the camera file to write: an existing file that is not a camera file (here the
// sequence's own target.yaml and rgb.txt) is refused before anything is read, and left as it was;
// the sequence's camera.yaml is replaced, even one whose values are refused (another image size),
// which calibrate does not read; a new folder is made for it.
TEST(CalibrateCommand, OutNeverOverwritesAnInput) {
  test::TempDir dir;
  const std::string seq = dir.file("seq");
  ASSERT_EQ(test::runSlamcmp("synth --preset handheld_rpy --frames 120 --supersample 1 --out " + seq).exit_code, 0);
  const auto calibrate = [&](const std::string& out) {
    return test::runSlamcmp("calibrate --sequence " + seq + " --target " + seq + "/target.yaml --out " + out);
  };
  for (const auto& [input, said] : {std::pair<std::string, std::string>{"target.yaml", " exists and is not a camera file"},
                                    {"rgb.txt", ": a camera file is written as YAML: name it .yaml or .yml"},
                                    {"rgb/000000.png", ": a camera file is written as YAML"}}) {
    const std::string path = seq + "/" + input;
    const std::vector<std::string> before = test::readLines(path);
    const auto r = calibrate(path);
    EXPECT_EQ(r.exit_code, 2) << input;
    EXPECT_NE(r.err.find("--out: " + path + said), std::string::npos) << r.err;
    EXPECT_EQ(test::readLines(path), before) << input;
  }
  CameraModel wrong_size = readCameraYaml(seq + "/camera.yaml");
  wrong_size.width = 320;
  wrong_size.height = 240;
  writeCameraYaml(seq + "/camera.yaml", wrong_size);
  const auto r = calibrate(seq + "/camera.yaml");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(readCameraYaml(seq + "/camera.yaml").width, 640);
  EXPECT_EQ(calibrate(dir.file("new/folder/camera.yaml")).exit_code, 0);
  EXPECT_EQ(readCameraYaml(dir.file("new/folder/camera.yaml")).height, 480);
}

// The phone video's board has 8x6 inner corners: symmetric (its origin is ambiguous), which does
// not matter to calibration. No published result: the principal point must be near the centre of
// the 1280x720 image and both focal lengths agree within 2 %. `run` with that camera keeps one origin
// (symmetric_board_test) and poses most frames (measured: all 241).
TEST(CalibrateCommand, PhoneVideoWithASymmetricBoard) {
  SLAMCMP_REQUIRE_SHARED(shared);
  test::TempDir dir;
  ASSERT_EQ(runCalibrate(shared + "/video_chessboard/chessboard.avi", {8, 6, 1.0}, dir), 0);
  const CameraModel c = readCameraYaml(dir.file("camera.yaml"));
  EXPECT_EQ(c.width, 1280);
  EXPECT_NEAR(c.cx, 640, 0.05 * 1280);
  EXPECT_NEAR(c.cy, 360, 0.05 * 720);
  EXPECT_NEAR(c.fx / c.fy, 1.0, 0.02);
  const auto run = test::runSlamcmp("run --backend cslam --sequence " + shared +
                                    "/video_chessboard/chessboard.avi --camera " + dir.file("camera.yaml") +
                                    " --out " + dir.file("run"));
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const size_t at = run.out.find("cslam: ");  // "cslam: 241/241 frames tracked, ..."
  ASSERT_NE(at, std::string::npos) << run.out;
  EXPECT_GE(std::stoi(run.out.substr(at + 7)), 229) << run.out;  // 95 % of 241
}

}  // namespace
}  // namespace slamcmp
