#pragma once
// `run --show`: the drawn frames in a live window, where a display exists.
#include <memory>
#include <string>

#include <opencv2/core.hpp>

#include "core/media_plugin.h"

namespace slamcmp {

// Throws InputError("--show", ...) when no window can be opened here: OpenCV built without a GUI
// back-end, or (Linux) DISPLAY and WAYLAND_DISPLAY unset or naming an X server that is not there.
// Called before any work, so a run never ends in a GUI toolkit's abort.
void requireDisplay();

class OverlayWindow {
 public:
  OverlayWindow() = default;
  OverlayWindow(const OverlayWindow&) = delete;
  OverlayWindow& operator=(const OverlayWindow&) = delete;

  // Shows `image` (opening the window on the first call). False once the user pressed q or Esc or
  // closed the window: the run then stops as Ctrl-C stops it.
  bool show(const cv::Mat& image);

 private:
  std::unique_ptr<ImageWindow> window_;  // opened by the first show()
};

}  // namespace slamcmp
