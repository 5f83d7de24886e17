#pragma once
// What `run --overlay FILE` and `run --show` do with each tracked frame: draw it once, then write
// it and/or show it.
#include <optional>
#include <string>

#include "eval/overlay/overlay_drawing.h"
#include "eval/overlay/overlay_window.h"
#include "eval/overlay/overlay_writer.h"

namespace slamcmp {

class OverlayOutput {
 public:
  // path "": no file; show: a live window (call requireDisplay() first, before any work). Throws
  // InputError as OverlayWriter does.
  OverlayOutput(const std::string& path, bool show, cv::Size image_size, double fps);

  // False once the user asked the window to stop (q, Esc, or closing it).
  bool add(const Frame& frame, const FrameResult& result);

 private:
  OverlayDrawer drawer_;
  std::optional<OverlayWriter> writer_;
  std::optional<OverlayWindow> window_;
};

}  // namespace slamcmp
