// Ctrl-C (SIGINT), `kill` (SIGTERM) or a closed terminal (SIGHUP) in the middle of `slamcmp run`
// (issue 7): the run stops at the next frame, leaves a valid trajectory.txt, frames.csv and
// summary.json ("interrupted": true) for the frames done, and exits 130.
#include <fcntl.h>
#include <sys/stat.h>
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "core/frames_csv.h"
#include "core/trajectory.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

using test::TempDir;

int countLines(const std::string& path) {
  std::ifstream in(path);
  int n = 0;
  std::string line;
  while (std::getline(in, line)) ++n;
  return n;
}

// Starts `bin args...` with stdout and stderr into files; returns its pid.
pid_t spawn(const std::vector<std::string>& argv, const std::string& out, const std::string& err) {
  const pid_t pid = fork();
  if (pid == 0) {
    const int o = open(out.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int e = open(err.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(o, 1);
    dup2(e, 2);
    // As from a terminal: whatever the test runner ignores (nohup: SIGHUP), the run hears.
    for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) std::signal(signal_number, SIG_DFL);
    std::vector<char*> args;
    for (const auto& a : argv) args.push_back(const_cast<char*>(a.c_str()));
    args.push_back(nullptr);
    execv(args[0], args.data());
    _exit(127);
  }
  return pid;
}

// Waits for `pid` up to `limit`; kills it (a hang is a failure) and returns -1 past that.
int waitExit(pid_t pid, std::chrono::seconds limit) {
  const auto deadline = std::chrono::steady_clock::now() + limit;
  int status = 0;
  while (waitpid(pid, &status, WNOHANG) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, &status, 0);
      return -1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// Runs cslam on a long sequence, sends `signal_number` once a few frames are recorded, and checks
// the outputs are whole.
void expectValidOutputsAfter(int signal_number) {
  const char* bin = std::getenv("SLAMCMP_BIN");
  ASSERT_NE(bin, nullptr) << "run through ctest (SLAMCMP_BIN)";
  TempDir tmp;
  const auto rendered =
      test::runSlamcmp("synth --preset tv1 --frames 60 --supersample 1 --out " + tmp.file("tv1"));
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;

  // A long sequence from the 60 rendered frames, played forth 20 times (1200 frames): long enough
  // that the run is still going when the signal arrives, however fast the back-end.
  const std::string seq = tmp.file("long");
  test::writeLoopedSequence(seq, "tv1", 60, 1200);

  const std::string out = tmp.file("run");
  const pid_t pid = spawn({bin, "run", "--backend", "cslam", "--sequence", seq, "--out", out},
                          tmp.file("stdout"), tmp.file("stderr"));
  ASSERT_GT(pid, 0);
  // Interrupt once a few frames are recorded (header + 3 rows); give up (and fail) after 2 minutes.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  while (countLines(out + "/frames.csv") < 4 && std::chrono::steady_clock::now() < deadline &&
         waitpid(pid, nullptr, WNOHANG) == 0)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_GE(countLines(out + "/frames.csv"), 4) << "the run recorded no frames";
  kill(pid, signal_number);
  const int code = waitExit(pid, std::chrono::seconds(60));
  std::stringstream stream;
  stream << std::ifstream(tmp.file("stderr")).rdbuf();
  const std::string err = stream.str();
  // 130, as a shell reports a command stopped by Ctrl-C: not a finished run, though its files are whole.
  ASSERT_EQ(code, 130) << "the run interrupted by signal " << signal_number << "; stderr: " << err;
  EXPECT_EQ(err.rfind("slamcmp: interrupted after ", 0), 0u) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;

  std::ifstream summary_file(out + "/summary.json");
  ASSERT_TRUE(summary_file) << "no summary.json";
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  EXPECT_EQ(summary["interrupted"], true);
  const int frames = summary["frames"].get<int>();
  EXPECT_GE(frames, 3);
  EXPECT_LT(frames, 1200) << "the run was not stopped early";

  const std::vector<FrameRow> rows = readFramesCsv(out + "/frames.csv");
  ASSERT_EQ(static_cast<int>(rows.size()), frames) << "frames.csv and summary.json disagree";
  for (size_t i = 0; i < rows.size(); ++i) EXPECT_EQ(rows[i].frame, static_cast<int>(i));

  const int tracked = summary["tracked"].get<int>();
  if (tracked > 0) {
    const Trajectory trajectory = readTrajectory(out + "/trajectory.txt", TrajectoryFormat::Tum);
    EXPECT_EQ(static_cast<int>(trajectory.size()), tracked);
    EXPECT_LE(trajectory.back().timestamp, rows.back().timestamp + 1e-6);
  } else {
    EXPECT_EQ(countLines(out + "/trajectory.txt"), 1) << "only the header";
  }
}

TEST(Interrupt, CtrlCLeavesValidOutputsForTheFramesDone) { expectValidOutputsAfter(SIGINT); }
TEST(Interrupt, SigtermLeavesValidOutputsForTheFramesDone) { expectValidOutputsAfter(SIGTERM); }
TEST(Interrupt, SighupLeavesValidOutputsForTheFramesDone) { expectValidOutputsAfter(SIGHUP); }

// `synth` stopped by SIGTERM: the frames rendered are a sequence of their own (rgb.txt and
// groundtruth.txt list them), and it exits 130. It was killed with 143, leaving images with no list.
TEST(Interrupt, SynthListsTheFramesItRendered) {
  const char* bin = std::getenv("SLAMCMP_BIN");
  ASSERT_NE(bin, nullptr) << "run through ctest (SLAMCMP_BIN)";
  TempDir tmp;
  const std::string out = tmp.file("seq");
  const pid_t pid = spawn({bin, "synth", "--preset", "tv1", "--frames", "5000", "--supersample", "1", "--out", out},
                          tmp.file("stdout"), tmp.file("stderr"));
  ASSERT_GT(pid, 0);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::minutes(2);
  const auto images = [&] {
    std::error_code ec;
    const auto n = std::distance(std::filesystem::directory_iterator(out + "/rgb", ec),
                                 std::filesystem::directory_iterator());
    return ec ? 0 : static_cast<int>(n);
  };
  while (images() < 4 && std::chrono::steady_clock::now() < deadline && waitpid(pid, nullptr, WNOHANG) == 0)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  ASSERT_GE(images(), 4) << "synth rendered nothing";
  kill(pid, SIGTERM);
  const int code = waitExit(pid, std::chrono::seconds(60));
  std::stringstream stream;
  stream << std::ifstream(tmp.file("stderr")).rdbuf();
  const std::string err = stream.str();
  ASSERT_EQ(code, 130) << err;
  EXPECT_NE(err.find("slamcmp: interrupted: " + out + " holds the first "), std::string::npos) << err;
  const Trajectory groundtruth = readTrajectory(out + "/groundtruth.txt");
  EXPECT_GE(groundtruth.size(), 3u);
  EXPECT_LT(groundtruth.size(), 5000u);
  EXPECT_EQ(countLines(out + "/rgb.txt"), static_cast<int>(groundtruth.size()) + 1);  // and its comment line
  // info.yaml says as much (compare --trials renders each trial from it).
  const std::vector<std::string> info = test::readLines(out + "/info.yaml");
  EXPECT_NE(std::find(info.begin(), info.end(),
                      "frames: " + std::to_string(groundtruth.size()) +
                          "  # 0: the preset's own length; more repeats its motion"),
            info.end());
  const auto run = test::runSlamcmp("run --backend cslam --sequence " + out + " --out " + tmp.file("run"));
  EXPECT_EQ(run.exit_code, 0) << run.err;
}

// Ctrl-C while rgb.txt is still being read (here a pipe the test feeds line by line; a list of a
// million lines on a slow disk alike): the run says it was interrupted, at the line it reached,
// never that the sequence has no frames, and exits 130 as an interrupted run does, not 2 (bad input).
TEST(Interrupt, WhileTheListIsBeingReadSaysSo) {
  const char* bin = std::getenv("SLAMCMP_BIN");
  ASSERT_NE(bin, nullptr) << "run through ctest (SLAMCMP_BIN)";
  TempDir tmp;
  const std::string seq = tmp.file("seq");
  std::filesystem::create_directories(seq + "/rgb");
  const auto rendered = test::runSlamcmp("synth --preset tv1 --frames 1 --supersample 1 --out " + tmp.file("tv1"));
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  std::filesystem::copy_file(tmp.file("tv1/rgb/000000.png"), seq + "/rgb/0.png");
  ASSERT_EQ(mkfifo((seq + "/rgb.txt").c_str(), 0644), 0);

  const pid_t pid = spawn({bin, "run", "--backend", "cslam", "--sequence", seq, "--out", tmp.file("out")},
                          tmp.file("stdout"), tmp.file("stderr"));
  ASSERT_GT(pid, 0);
  const auto previous = std::signal(SIGPIPE, SIG_IGN);  // should the run end before the pipe does
  const int list = open((seq + "/rgb.txt").c_str(), O_WRONLY);  // once the run opens it to read
  ASSERT_GE(list, 0);
  const std::string first = "0.0 rgb/0.png\n", second = "0.1 rgb/0.png\n";
  EXPECT_EQ(write(list, first.data(), first.size()), static_cast<ssize_t>(first.size()));
  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the run waits for line 2
  kill(pid, SIGINT);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(write(list, second.data(), second.size()), static_cast<ssize_t>(second.size()));
  close(list);
  std::signal(SIGPIPE, previous);

  const int code = waitExit(pid, std::chrono::seconds(60));
  std::stringstream stream;
  stream << std::ifstream(tmp.file("stderr")).rdbuf();
  const std::string err = stream.str();
  EXPECT_EQ(code, 130) << err;
  // At line 2, unless the machine was too busy to read line 1 before the signal came.
  EXPECT_EQ(err.rfind("slamcmp: " + seq + "/rgb.txt:", 0), 0u) << err;
  EXPECT_NE(err.find(": interrupted while the list was being read\n"), std::string::npos) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
}

// Ctrl-C before the first frame (here while groundtruth.txt, read after the image list, is a pipe
// the test feeds): the run still writes its outputs whole, a run of 0 frames with "interrupted":
// true and no timings (null, not NaN), and exits 130; --collect counts it interrupted, not failed
// (a probe found no summary.json, which --collect took for a failed run).
TEST(Interrupt, BeforeTheFirstFrameLeavesASummaryOfNoFrames) {
  ASSERT_NE(std::getenv("SLAMCMP_BIN"), nullptr) << "run through ctest (SLAMCMP_BIN)";
  TempDir tmp;
  const std::string seq = tmp.file("seq");
  const auto rendered = test::runSlamcmp("synth --preset tv1 --frames 3 --supersample 1 --out " + seq);
  ASSERT_EQ(rendered.exit_code, 0) << rendered.err;
  const std::string plan = tmp.file("plan");
  const auto planned = test::runSlamcmp("compare --sequence " + seq + " --backends cslam --plan " + plan);
  ASSERT_EQ(planned.exit_code, 0) << planned.err;
  std::ifstream plan_file(plan + "/plan.json");
  const nlohmann::json run = nlohmann::json::parse(plan_file)["runs"].at(0);
  const std::string out = plan + "/" + run["dir"].get<std::string>();

  const std::string groundtruth = seq + "/groundtruth.txt";
  std::stringstream groundtruth_text;
  groundtruth_text << std::ifstream(groundtruth).rdbuf();
  std::filesystem::rename(groundtruth, tmp.file("groundtruth.txt"));
  ASSERT_EQ(mkfifo(groundtruth.c_str(), 0644), 0);
  const pid_t pid = spawn(run["argv"].get<std::vector<std::string>>(), tmp.file("stdout"), tmp.file("stderr"));
  ASSERT_GT(pid, 0);
  const auto previous = std::signal(SIGPIPE, SIG_IGN);  // should the run end before the pipe does
  const int pipe = open(groundtruth.c_str(), O_WRONLY);  // once the run, past the image list, opens it
  ASSERT_GE(pipe, 0);
  kill(pid, SIGINT);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  const std::string text = groundtruth_text.str();
  EXPECT_EQ(write(pipe, text.data(), text.size()), static_cast<ssize_t>(text.size()));
  close(pipe);
  std::signal(SIGPIPE, previous);
  const int code = waitExit(pid, std::chrono::seconds(60));
  std::filesystem::remove(groundtruth);
  std::filesystem::rename(tmp.file("groundtruth.txt"), groundtruth);  // as --collect reads it

  std::stringstream stream;
  stream << std::ifstream(tmp.file("stderr")).rdbuf();
  const std::string err = stream.str();
  ASSERT_EQ(code, 130) << err;
  EXPECT_EQ(err.rfind("slamcmp: interrupted after 0 frames", 0), 0u) << err;
  EXPECT_EQ(std::count(err.begin(), err.end(), '\n'), 1) << err;
  std::ifstream summary_file(out + "/summary.json");
  ASSERT_TRUE(summary_file) << "no summary.json";
  const nlohmann::json summary = nlohmann::json::parse(summary_file);
  EXPECT_EQ(summary["interrupted"], true);
  EXPECT_EQ(summary["frames"], 0);
  EXPECT_EQ(summary["tracked"], 0);
  for (const char* timing : {"ms_per_frame", "cpu_ms_per_frame"})
    for (const char* statistic : {"median", "mean", "p99", "max"})
      EXPECT_TRUE(summary[timing][statistic].is_null()) << timing << "." << statistic << ": " << summary[timing];
  EXPECT_FALSE(summary.contains("ate"));
  EXPECT_EQ(countLines(out + "/frames.csv"), 1) << "only the header";
  EXPECT_EQ(countLines(out + "/trajectory.txt"), 1) << "only the header";

  const auto collected = test::runSlamcmp("compare --collect " + plan);
  EXPECT_EQ(collected.exit_code, 0) << collected.err;
  std::stringstream report;
  report << std::ifstream(plan + "/report.md").rdbuf();
  EXPECT_NE(report.str().find("`" + run["dir"].get<std::string>() + "`: interrupted: stopped after 0 frames"),
            std::string::npos)
      << report.str();
}

}  // namespace
}  // namespace slamcmp
