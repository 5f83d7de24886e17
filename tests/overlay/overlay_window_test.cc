// `run --show`'s window: refused with one clear message where no display exists, and kept open
// frame after frame where one does (Qt's offscreen platform stands in for a display here).
#include "eval/overlay/overlay_window.h"

#include <cstdlib>

#include <gtest/gtest.h>

#include "core/error.h"

namespace slamcmp {
namespace {

TEST(OverlayWindow, NoDisplayIsRefusedWithAHint) {
  unsetenv("DISPLAY");
  unsetenv("WAYLAND_DISPLAY");
  try {
    requireDisplay();
    FAIL() << "requireDisplay() accepted an environment without a display";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--show"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("--overlay FILE"), std::string::npos) << e.what();
  }
}

TEST(OverlayWindow, StaleLocalXDisplayIsRefused) {
  unsetenv("WAYLAND_DISPLAY");
  setenv("DISPLAY", ":987.0", 1);
  EXPECT_THROW(requireDisplay(), InputError);
}

TEST(OverlayWindow, QtWithOnlyAWaylandDisplayIsRefusedUnlessToldToUseIt) {
  if (cv::getBuildInformation().find("QT") == std::string::npos)
    GTEST_SKIP() << "OpenCV's GUI back-end is not Qt";
  unsetenv("DISPLAY");
  unsetenv("QT_QPA_PLATFORM");
  setenv("WAYLAND_DISPLAY", "wayland-0", 1);
  EXPECT_THROW(requireDisplay(), InputError);  // Qt would pick X11 and abort
  setenv("QT_QPA_PLATFORM", "wayland", 1);
  EXPECT_NO_THROW(requireDisplay());
}

TEST(OverlayWindow, KeepsShowingFramesWhileTheWindowIsOpen) {
  if (cv::getBuildInformation().find("QT") == std::string::npos)
    GTEST_SKIP() << "OpenCV's GUI back-end is not Qt: no offscreen display to test with";
  setenv("QT_QPA_PLATFORM", "offscreen", 1);
  setenv("WAYLAND_DISPLAY", "offscreen-test", 1);
  ASSERT_NO_THROW(requireDisplay());
  OverlayWindow window;
  const cv::Mat image(120, 160, CV_8UC3, cv::Scalar(0, 0, 255));
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(window.show(image)) << "frame " << i;
}

}  // namespace
}  // namespace slamcmp
