#include "eval/overlay/overlay_output.h"

namespace slamcmp {

OverlayOutput::OverlayOutput(const std::string& path, bool show, cv::Size image_size, double fps) {
  if (!path.empty()) writer_.emplace(path, image_size, fps);
  if (show) window_.emplace();
}

bool OverlayOutput::add(const Frame& frame, const FrameResult& result) {
  std::vector<DrawnPrimitive> drawn;
  const cv::Mat image = drawer_.draw(frame, result, &drawn);
  if (writer_) writer_->write(frame.index, image, drawn);
  return !window_ || window_->show(image);
}

}  // namespace slamcmp
