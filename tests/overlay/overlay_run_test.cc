// `slamcmp run --overlay` end to end on a short rendered sequence: one PNG a frame at the
// sequence's size, overlay.csv's board corners where the ground truth projects the board, and the
// corner marker's colour at those pixels (the features' colours at theirs). Also the video output and --show without a display.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/videoio.hpp>

#include "core/camera.h"
#include "core/frames_csv.h"
#include "core/target.h"
#include "core/trajectory.h"
#include "datasets/synth_sequence.h"
#include "eval/overlay/overlay_drawing.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

using test::TempDir;

constexpr int kFrames = 4;

struct CsvRow {
  int frame = 0;
  std::string kind;
  int id = 0;
  Vec2 uv;
  std::string state;
};

std::vector<CsvRow> readOverlayCsv(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "frame,kind,id,u,v,state") << path;
  std::vector<CsvRow> rows;
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    std::vector<std::string> f;
    for (std::string field; std::getline(fields, field, ',');) f.push_back(field);
    if (f.size() == 5 && line.back() == ',') f.push_back("");
    EXPECT_EQ(f.size(), 6u) << path << ": " << line;
    if (f.size() != 6) continue;
    rows.push_back({std::stoi(f[0]), f[1], std::stoi(f[2]), Vec2(std::stod(f[3]), std::stod(f[4])), f[5]});
  }
  return rows;
}

// Whether some pixel within `radius` of uv has exactly `colour`.
bool colourNear(const cv::Mat& image, const Vec2& uv, const cv::Scalar& colour, int radius) {
  const cv::Vec3b want(static_cast<uint8_t>(colour[0]), static_cast<uint8_t>(colour[1]), static_cast<uint8_t>(colour[2]));
  const int u = static_cast<int>(std::lround(uv.x())), v = static_cast<int>(std::lround(uv.y()));
  for (int y = std::max(0, v - radius); y <= std::min(image.rows - 1, v + radius); ++y)
    for (int x = std::max(0, u - radius); x <= std::min(image.cols - 1, u + radius); ++x)
      if (image.at<cv::Vec3b>(y, x) == want) return true;
  return false;
}

std::string pngName(int frame) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%06d.png", frame);
  return name;
}

// An overlay.csv board corner lies within 1 px of where the ground truth projects the target's
// corner of its id (index j * cols + i, SPEC section 2).
void expectCornerAtItsTruth(const CsvRow& row, const std::string& sequence, const std::vector<FrameRow>& frames) {
  const CameraModel camera = readCameraYaml(sequence + "/camera.yaml");
  const ChessboardTarget target = readTargetYaml(sequence + "/target.yaml");
  const Trajectory groundtruth = readTrajectory(sequence + "/groundtruth.txt");
  ASSERT_GE(row.id, 0);
  ASSERT_LT(row.id, target.numCorners());
  const FrameRow& f = frames.at(row.frame);
  const StampedPose* gt = nullptr;
  for (const StampedPose& p : groundtruth)
    if (std::abs(p.timestamp - f.timestamp) < 1e-6) gt = &p;
  ASSERT_NE(gt, nullptr) << "no ground truth at " << f.timestamp;
  const Vec3 p_world = target.cornerWorld(row.id % target.cols, row.id / target.cols);
  const Vec2 uv_truth = camera.project(gt->T_world_camera.inverse() * p_world);
  EXPECT_LT((row.uv - uv_truth).norm(), 1.0) << "frame " << row.frame << " corner " << row.id;
}

class OverlayRun : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir;
    SynthOptions options;
    options.preset = "tv1";
    options.frames = kFrames;
    writeSyntheticSequence(options, sequence());
  }
  static void TearDownTestSuite() { delete dir_; }
  static std::string sequence() { return dir_->file("tv1"); }
  static TempDir* dir_;
};
TempDir* OverlayRun::dir_ = nullptr;

TEST_F(OverlayRun, CslamPngsShowTheBoardWhereTheGroundTruthProjectsIt) {
  TempDir tmp;
  const std::string overlay = tmp.file("overlay");
  const test::CommandResult r = test::runSlamcmp("run --backend cslam --sequence " + sequence() + " --out " +
                                                 tmp.file("out") + " --overlay " + overlay);
  ASSERT_EQ(r.exit_code, 0) << r.err;

  const CameraModel camera = readCameraYaml(sequence() + "/camera.yaml");
  const ChessboardTarget target = readTargetYaml(sequence() + "/target.yaml");
  const std::vector<FrameRow> frames = readFramesCsv(tmp.file("out/frames.csv"));
  ASSERT_EQ(frames.size(), static_cast<size_t>(kFrames));
  std::map<int, cv::Mat> pngs;
  for (const FrameRow& f : frames) {
    const cv::Mat png = cv::imread(overlay + "/" + pngName(f.frame), cv::IMREAD_COLOR);
    ASSERT_FALSE(png.empty()) << pngName(f.frame);
    EXPECT_EQ(png.size(), cv::Size(camera.width, camera.height));
    pngs[f.frame] = png;
  }

  std::map<int, int> corners_in_frame;
  int features = 0;
  for (const CsvRow& row : readOverlayCsv(overlay + "/overlay.csv")) {
    if (row.kind == "feature") {
      // Inliers are rings and rejected features crosses, a few pixels across: their colour is there.
      ASSERT_TRUE(pngs.count(row.frame)) << "overlay.csv names frame " << row.frame;
      const bool inlier = row.state == "inlier";
      EXPECT_TRUE(inlier || row.state == "rejected") << row.state;
      const cv::Scalar want = inlier ? overlay_colour::kInlier : overlay_colour::kRejected;
      EXPECT_TRUE(colourNear(pngs[row.frame], row.uv, want, 5)) << "frame " << row.frame << " feature " << row.id;
      ++features;
      continue;
    }
    if (row.kind != "board_corner") continue;
    ASSERT_TRUE(pngs.count(row.frame)) << "overlay.csv names frame " << row.frame;
    expectCornerAtItsTruth(row, sequence(), frames);
    const cv::Point pixel(static_cast<int>(std::lround(row.uv.x())), static_cast<int>(std::lround(row.uv.y())));
    const cv::Scalar red = overlay_colour::kBoardCorner;
    EXPECT_EQ(pngs[row.frame].at<cv::Vec3b>(pixel), cv::Vec3b(red[0], red[1], red[2]))
        << "frame " << row.frame << " corner " << row.id;
    ++corners_in_frame[row.frame];
  }
  // Every frame posed from the board shows all its corners; tv1 keeps the board in view.
  int board_frames = 0;
  for (const FrameRow& f : frames)
    if (f.source == "board") {
      EXPECT_EQ(corners_in_frame[f.frame], target.numCorners()) << "frame " << f.frame;
      ++board_frames;
    }
  EXPECT_GE(board_frames, 1);
  EXPECT_GT(features, 0);
}

// Where part of the board has left the image (board_partial from frame 17), each corner listed is
// still the target's corner of its id, for cslam and hybrid; and hybrid draws the corners of the
// frame it starts from.
TEST(OverlayRunPartialBoard, CornersKeepTheTargetsIds) {
  TempDir tmp;
  SynthOptions synth;
  synth.preset = "board_partial";
  synth.frames = 20;
  synth.supersample = 1;
  writeSyntheticSequence(synth, tmp.file("bp"));
  for (const char* backend : {"cslam", "hybrid"}) {
    const std::string out = tmp.file(std::string("out_") + backend);
    const test::CommandResult r = test::runSlamcmp(std::string("run --backend ") + backend + " --sequence " +
                                                   tmp.file("bp") + " --out " + out + " --overlay " + out + "/ov");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::vector<FrameRow> frames = readFramesCsv(out + "/frames.csv");
    std::map<int, int> corners_in_frame;
    for (const CsvRow& row : readOverlayCsv(out + "/ov/overlay.csv")) {
      if (row.kind != "board_corner") continue;
      expectCornerAtItsTruth(row, tmp.file("bp"), frames);
      ++corners_in_frame[row.frame];
    }
    EXPECT_EQ(corners_in_frame[0], 54) << backend;  // the start
    int partial = 0;
    for (const auto& [frame, corners] : corners_in_frame) partial += corners >= 27 && corners < 54;
    EXPECT_GE(partial, 2) << backend;
  }
}

TEST_F(OverlayRun, MonoslamPngsAreWrittenForEveryFrame) {
  TempDir tmp;
  const test::CommandResult r = test::runSlamcmp("run --backend monoslam --sequence " + sequence() + " --out " +
                                                 tmp.file("out") + " --overlay " + tmp.file("ov"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (int i = 0; i < kFrames; ++i) EXPECT_TRUE(std::filesystem::exists(tmp.file("ov/" + pngName(i)))) << i;
  for (const CsvRow& row : readOverlayCsv(tmp.file("ov/overlay.csv"))) {
    EXPECT_GE(row.frame, 0);
    EXPECT_LT(row.frame, kFrames);
  }
}

TEST_F(OverlayRun, VideoHoldsEveryFrameAndItsCsvSitsBeside) {
  TempDir tmp;
  const std::string video = tmp.file("clips/overlay.avi");
  const test::CommandResult r = test::runSlamcmp("run --backend cslam --sequence " + sequence() + " --out " +
                                                 tmp.file("out") + " --overlay " + video);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  cv::VideoCapture capture(video, cv::CAP_FFMPEG);
  ASSERT_TRUE(capture.isOpened()) << video;
  EXPECT_NEAR(capture.get(cv::CAP_PROP_FPS), 10.0, 1e-3);  // tv1's rate, from its timestamps
  int frames = 0;
  for (cv::Mat image; capture.read(image); ++frames) EXPECT_EQ(image.size(), cv::Size(640, 480));
  EXPECT_EQ(frames, kFrames);
  EXPECT_TRUE(std::filesystem::exists(video + ".csv"));
}

TEST(OverlayShow, WithoutADisplayFailsBeforeAnyWork) {
  TempDir tmp;
  unsetenv("DISPLAY");  // the child inherits the test's environment
  unsetenv("WAYLAND_DISPLAY");
  const test::CommandResult r = test::runSlamcmp("run --backend cslam --sequence " + tmp.file("none") +
                                                 " --out " + tmp.file("out") + " --show");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find("--show: needs a display"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("--overlay FILE"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(tmp.file("out")));
}

}  // namespace
}  // namespace slamcmp
