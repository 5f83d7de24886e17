// slamcmp: runs monocular SLAM back-ends side by side and scores them.
// Exit codes: 0 done, 2 bad usage or bad input (one line on stderr), 1 internal failure, 130 an
// interrupted run, compare or reproduce.
#include <cstdio>
#include <cstdlib>
#include <iostream>

#include <CLI/CLI.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/core/utils/logger.hpp>

#include "core/frame_memory.h"
#include "eval/app/cli.h"

int main(int argc, char** argv) {
  slamcmp::keepFreedMemoryForReuse();  // before the decoding threads start
  // OpenCV's own messages (e.g. from a broken image) must not interleave with ours.
  cv::redirectError([](int, const char*, const char*, const char*, int, void*) { return 0; });
  // Nor its logging, nor the video libraries' (a file that is not a video makes FFmpeg and
  // GStreamer print several lines); the user's own settings of these variables win.
  cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_SILENT);
  setenv("OPENCV_FFMPEG_LOGLEVEL", "-8", 0);  // AV_LOG_QUIET
  setenv("OPENCV_VIDEOIO_PRIORITY_GSTREAMER", "0", 0);  // FFmpeg reads the files we read
  CLI::App app{
      "slamcmp: runs monocular SLAM back-ends (`slamcmp run --help` lists them) on the same image sequences "
      "and scores them against ground truth."};
  slamcmp::addCommands(app);
  return slamcmp::runCommandLine(app, argc, argv, std::cout, std::cerr);
}
