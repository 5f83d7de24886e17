// `run --threads N`: a run gives OpenCV N threads (1 by default: see RunRequest::opencv_threads),
// says so in summary.json, and leaves OpenCV's setting as it found it.
#include <algorithm>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>

#include "core/error.h"
#include "eval/app/run_sequence.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

TEST(OpenCvThreads, ARunTracksOnTheThreadsItIsGivenAndRestoresOpenCvsSetting) {
  test::TempDir tmp;
  ASSERT_EQ(test::runSlamcmp("synth --preset tv1 --frames 4 --supersample 1 --out " + tmp.file("tv1")).exit_code, 0);
  const auto runRequest = [&](int threads) {
    RunRequest request;
    request.backend = "cslam";
    request.sequence_path = tmp.file("tv1");
    request.out_dir = tmp.file("run" + std::to_string(threads));
    request.progress = false;
    if (threads != 1) request.opencv_threads = threads;  // 1: the default
    return request;
  };
  const int before = cv::getNumThreads();
  const int hardware_threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  for (const int threads : {1, std::min(2, hardware_threads)}) {  // OpenCV's own default: a thread per core
    RunRequest request = runRequest(threads);
    std::vector<int> seen;
    request.on_frame = [&seen] { seen.push_back(cv::getNumThreads()); };
    const nlohmann::json summary = runSequence(request);
    EXPECT_EQ(summary["opencv_threads"], threads);
    ASSERT_EQ(seen.size(), 4u);
    for (const int n : seen) EXPECT_EQ(n, threads);
    EXPECT_EQ(cv::getNumThreads(), before);
  }
  EXPECT_THROW(runSequence(runRequest(0)), InputError);
  // More than the machine has: refused (OpenCV's TBB pool warned from 8, and crashed past 65536).
  EXPECT_THROW(runSequence(runRequest(hardware_threads + 1)), InputError);
  const auto many = test::runSlamcmp("run --backend cslam --threads 65537 --sequence " + tmp.file("tv1") +
                                     " --out " + tmp.file("many"));
  EXPECT_EQ(many.exit_code, 2) << many.err;
  EXPECT_NE(many.err.find("--threads: must be in [1, "), std::string::npos) << many.err;
  const auto bad = test::runSlamcmp("run --backend cslam --threads 0 --sequence " + tmp.file("tv1"));
  EXPECT_EQ(bad.exit_code, 2) << bad.err;
  EXPECT_NE(bad.err.find("--threads"), std::string::npos) << bad.err;
}

}  // namespace
}  // namespace slamcmp
