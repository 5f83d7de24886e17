// Faults inside a run (issue 7): frames with nothing to see and a frame that cannot be decoded.
// Each back-end reports those frames lost with a reason, never a made-up pose, and recovers when
// the board and the room come back.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include <opencv2/imgcodecs.hpp>

#include "core/frames_csv.h"
#include "core/trajectory.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

namespace fs = std::filesystem;
using test::TempDir;

constexpr int kFrames = 60;
constexpr int kBlankFirst = 20, kBlankLast = 31;  // a flat grey image: no board, no texture
constexpr int kUndecodable = 40;                  // a PNG whose bytes are garbage
// While the board is missing cslam runs its full search only every third frame
// (board.search_interval_when_lost), so it may see the board again up to two frames late.
constexpr int kCslamBackBy = kBlankLast + 3;

// A short tv1 rendered once for every test here, and a copy of its frame list with the faults in.
class FaultyTv1 : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    dir_ = new TempDir();
    const std::string clean = dir_->file("clean");
    const auto synth = test::runSlamcmp("synth --preset tv1 --frames " + std::to_string(kFrames) +
                                        " --supersample 1 --out " + clean);
    ASSERT_EQ(synth.exit_code, 0) << synth.err;

    const std::string faulty = dir_->file("faulty");
    fs::create_directories(faulty);
    for (const char* name : {"camera.yaml", "target.yaml", "groundtruth.txt"})
      fs::copy_file(clean + "/" + name, faulty + "/" + name);
    cv::imwrite(faulty + "/blank.png", cv::Mat(480, 640, CV_8UC1, cv::Scalar(128)));
    test::writeText(faulty + "/garbage.png", std::string("\x89PNG\r\n\x1a\n", 8) + std::string(5000, 'x'));

    std::ifstream in(clean + "/rgb.txt");
    std::ofstream out(faulty + "/rgb.txt");
    std::string line;
    int index = 0;
    while (std::getline(in, line)) {
      if (line.empty() || line[0] == '#') continue;
      std::istringstream fields(line);
      std::string timestamp, image;
      fields >> timestamp >> image;
      if (index >= kBlankFirst && index <= kBlankLast) image = "blank.png";
      else if (index == kUndecodable) image = "garbage.png";
      else image = clean + "/" + image;
      out << timestamp << ' ' << image << '\n';
      ++index;
    }
    ASSERT_EQ(index, kFrames);
  }
  static void TearDownTestSuite() { delete dir_; }

  struct Run {
    std::vector<FrameRow> rows;
    nlohmann::json summary;
    Trajectory poses;
    const StampedPose* poseAt(double timestamp) const {
      for (const StampedPose& p : poses)
        if (std::abs(p.timestamp - timestamp) < 1e-4) return &p;
      return nullptr;
    }
  };
  static Run run(const std::string& name, const std::string& args) {
    const std::string out = dir_->file("run_" + name);
    const auto result = test::runSlamcmp("run --sequence " + dir_->file("faulty") + " --out " + out + " " + args);
    EXPECT_EQ(result.exit_code, 0) << result.err;
    Run r;
    r.rows = readFramesCsv(out + "/frames.csv");
    std::ifstream summary(out + "/summary.json");
    r.summary = nlohmann::json::parse(summary);
    r.poses = readTrajectory(out + "/trajectory.txt", TrajectoryFormat::Tum);
    return r;
  }
  static double errorTo(const Run& r, int frame) {
    const Trajectory truth = readTrajectory(dir_->file("clean/groundtruth.txt"), TrajectoryFormat::Tum);
    const StampedPose& gt = truth.at(frame);
    return (r.poseAt(gt.timestamp)->T_world_camera.t() - gt.T_world_camera.t()).norm();
  }
  // The faults are reported, every posed frame is close to the truth, and tracking is back
  // from `recovered_by` on.
  static void expectFaultsReportedAndRecovered(const Run& r, int recovered_by, double tolerance_m) {
    ASSERT_EQ(static_cast<int>(r.rows.size()), kFrames);
    EXPECT_EQ(r.rows[kUndecodable].status, TrackStatus::Lost);
    EXPECT_EQ(r.summary["lost_reasons"].value("image could not be decoded", 0), 1) << r.summary.dump(1);
    for (const FrameRow& row : r.rows) {
      const bool posed = r.poseAt(row.timestamp) != nullptr;
      EXPECT_EQ(posed, row.status != TrackStatus::Lost && row.status != TrackStatus::Initialising)
          << "frame " << row.frame;
      if (posed) {
        EXPECT_LT(errorTo(r, row.frame), tolerance_m) << "frame " << row.frame;
      }
      if (row.frame >= recovered_by && row.frame != kUndecodable) {
        EXPECT_NE(row.status, TrackStatus::Lost) << "frame " << row.frame << " not recovered";
      }
    }
    for (const char* kind : {"lost", "initialising"}) {
      int reasons = 0;
      for (const auto& [reason, count] : r.summary[std::string(kind) + "_reasons"].items()) reasons += count.get<int>();
      EXPECT_EQ(reasons, r.summary[kind].get<int>()) << "every " << kind << " frame has a reason";
    }
    EXPECT_EQ(r.summary["tracked"].get<int>() + r.summary["lost"].get<int>() + r.summary["initialising"].get<int>(),
              r.summary["frames"].get<int>());
  }

  static TempDir* dir_;
};
TempDir* FaultyTv1::dir_ = nullptr;

TEST_F(FaultyTv1, CslamCombinedLosesTheBlankFramesAndRecoversWithTheBoard) {
  const Run r = run("cslam", "--backend cslam");
  for (int i = kBlankFirst; i <= kBlankLast; ++i) EXPECT_EQ(r.rows[i].status, TrackStatus::Lost) << i;
  EXPECT_EQ(r.rows[kCslamBackBy].source, "board");
  expectFaultsReportedAndRecovered(r, kCslamBackBy, 0.005);
}

TEST_F(FaultyTv1, CslamTwoViewRestartsFromTheBoardAfterTheBlankFrames) {
  const Run r = run("cslam_two_view", "--backend cslam --mode two_view");
  for (int i = kBlankFirst; i <= kBlankLast; ++i) EXPECT_EQ(r.rows[i].status, TrackStatus::Lost) << i;
  expectFaultsReportedAndRecovered(r, kCslamBackBy, 0.01);
}

TEST_F(FaultyTv1, MonoslamGoesLostWithoutMatchesAndRestartsFromTheBoard) {
  const Run r = run("monoslam", "--backend monoslam");
  // Prediction alone carries it a few frames; without a match for max_frames_unmeasured (10)
  // frames it must give up rather than keep extrapolating. The board's first frame back gives the
  // restart its motion (with the next), so the filter is back from the second.
  EXPECT_EQ(r.rows[kBlankLast].status, TrackStatus::Lost);
  EXPECT_EQ(r.rows[kBlankLast + 1].status, TrackStatus::Lost);
  expectFaultsReportedAndRecovered(r, kBlankLast + 2, 0.03);
}

}  // namespace
}  // namespace slamcmp
