// The video and window plugin: loaded only when needed, videos written and read back through it,
// and a clear error when it cannot be loaded.
#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "core/media_plugin.h"
#include "tests/test_util.h"

namespace slamcmp {
namespace {

bool mapped(const std::string& library) {
  std::ifstream maps("/proc/self/maps");
  std::stringstream all;
  all << maps.rdbuf();
  return all.str().find(library) != std::string::npos;
}

TEST(MediaPlugin, VideoAndWindowLibrariesLoadOnlyWhenAsked) {
  // Each ctest test is a process of its own, so nothing has opened a video here yet.
  EXPECT_FALSE(mapped("libopencv_videoio")) << "videoio is linked into slamcmp_core again";
  EXPECT_FALSE(mapped("libopencv_highgui")) << "highgui is linked into slamcmp_core again";
  mediaPlugin("test");
  EXPECT_TRUE(mapped("libopencv_videoio"));
}

TEST(MediaPlugin, VideoWrittenIsReadBackFrameByFrame) {
  test::TempDir tmp;
  const std::string path = tmp.file("clip.avi");
  const cv::Size size(64, 48);
  const int frames = 5;
  {
    auto writer = mediaPlugin(path).createVideo(path, "MJPG", 12.0, size);
    ASSERT_TRUE(writer);
    for (int i = 0; i < frames; ++i) writer->write(cv::Mat(size, CV_8UC3, cv::Scalar::all(40 * i + 20)));
  }
  auto reader = mediaPlugin(path).openVideo(path);
  ASSERT_TRUE(reader);
  EXPECT_EQ(reader->frameSize(), size);
  EXPECT_EQ(reader->frameCount(), frames);
  EXPECT_NEAR(reader->fps(), 12.0, 1e-6);
  int read = 0;
  for (cv::Mat bgr; reader->read(bgr); ++read) {
    ASSERT_EQ(bgr.size(), size);
    EXPECT_NEAR(cv::mean(bgr)[0], 40 * read + 20, 3.0) << "frame " << read;  // MJPG is lossy
  }
  EXPECT_EQ(read, frames);
}

TEST(MediaPlugin, WhatCannotBeOpenedIsNull) {
  test::TempDir tmp;
  test::writeText(tmp.file("clip.avi"), "not a video");
  EXPECT_FALSE(mediaPlugin("test").openVideo(tmp.file("clip.avi")));
  EXPECT_FALSE(mediaPlugin("test").openVideo(tmp.file("missing.avi")));
  EXPECT_FALSE(mediaPlugin("test").createVideo(tmp.file("x.avi"), "MJ", 30, cv::Size(64, 48)));
  EXPECT_FALSE(mediaPlugin("test").createVideo(tmp.file("no/such/folder/x.avi"), "MJPG", 30, cv::Size(64, 48)));
}

TEST(MediaPlugin, MissingPluginIsOneLineNamingTheVideo) {
  test::TempDir tmp;
  test::writeText(tmp.file("clip.avi"), "not a video");
  setenv("SLAMCMP_MEDIA_PLUGIN", tmp.file("no_plugin.so").c_str(), 1);  // inherited by the child
  const test::CommandResult r =
      test::runSlamcmp("run --backend cslam --sequence " + tmp.file("clip.avi") + " --out " + tmp.file("out"));
  unsetenv("SLAMCMP_MEDIA_PLUGIN");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  EXPECT_NE(r.err.find(tmp.file("clip.avi") + ": needs the video and window plugin"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(tmp.file("no_plugin.so")), std::string::npos) << r.err;
}

}  // namespace
}  // namespace slamcmp
