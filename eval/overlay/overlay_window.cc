#include "eval/overlay/overlay_window.h"

#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "core/error.h"

namespace slamcmp {

namespace {

constexpr const char* kWindow = "slamcmp run";
constexpr const char* kHint = "; use --overlay FILE to write the drawn frames instead";

// The "GUI:" line of OpenCV's build information ("QT5", "GTK3", "NONE", ...).
std::string guiBackend() {
  std::istringstream info(cv::getBuildInformation());
  for (std::string line; std::getline(info, line);) {
    const auto at = line.find("GUI:");
    if (at == std::string::npos) continue;
    const auto value = line.find_first_not_of(' ', at + 4);
    return value == std::string::npos ? "" : line.substr(value);
  }
  return "";
}

std::string environment(const char* name) {
  const char* value = std::getenv(name);
  return value ? value : "";
}

}  // namespace

void requireDisplay() {
  const std::string gui = guiBackend();
  if (gui.empty() || gui.rfind("NONE", 0) == 0)
    throw InputError("--show", std::string("needs a display, and this OpenCV was built without a GUI back-end") + kHint);
#ifdef __linux__
  const std::string x11 = environment("DISPLAY"), wayland = environment("WAYLAND_DISPLAY");
  if (x11.empty() && wayland.empty())
    throw InputError("--show", std::string("needs a display (DISPLAY and WAYLAND_DISPLAY are unset)") + kHint);
  // Qt picks its X11 plugin unless told otherwise, and aborts without an X display.
  if (gui.rfind("QT", 0) == 0 && x11.empty() && environment("QT_QPA_PLATFORM").empty())
    throw InputError("--show", std::string("needs an X display for OpenCV's Qt windows (DISPLAY is unset; set "
                                           "QT_QPA_PLATFORM=wayland to use Wayland)") + kHint);
  // A local X display ":N" whose socket is gone (a stale DISPLAY) would make the GUI toolkit abort.
  if (wayland.empty() && x11[0] == ':') {
    const std::string socket = "/tmp/.X11-unix/X" + x11.substr(1, x11.find('.') - 1);
    if (!std::filesystem::exists(socket))
      throw InputError("--show", "needs a display (DISPLAY=" + x11 + " but " + socket + " does not exist)" + kHint);
  }
#endif
  mediaPlugin("--show");  // the window's library, loaded now rather than after the first frame's work
}

bool OverlayWindow::show(const cv::Mat& image) {
  if (!window_) window_ = mediaPlugin("--show").openWindow(kWindow);
  const int key = window_->show(image);
  if (key == 'q' || key == 'Q' || key == 27) return false;
  return window_->visible();
}

}  // namespace slamcmp
