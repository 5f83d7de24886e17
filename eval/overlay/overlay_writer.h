#pragma once
// Where `run --overlay FILE` puts the drawn frames: a video (FILE ending in .avi, .mp4 or .mkv) or
// a folder of PNGs (frame_000000.png, ... numbered by frame index), and beside them overlay.csv,
// the drawn primitives' positions (frame,kind,id,u,v,state) for users and tests to check.
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/media_plugin.h"
#include "eval/overlay/overlay_drawing.h"

namespace slamcmp {

class OverlayWriter {
 public:
  // Creates the folder (or the video's folder) and opens the outputs; a video plays at `fps`, the
  // sequence's rate. Throws InputError naming `path` when it cannot be written or has an extension
  // that is not a supported container.
  OverlayWriter(const std::string& path, cv::Size image_size, double fps);

  // One drawn frame (BGR, image_size) and what was drawn on it. Throws InputError if writing fails.
  void write(int frame_index, const cv::Mat& image, const std::vector<DrawnPrimitive>& drawn);

 private:
  std::string path_;
  std::string csv_path_;  // overlay.csv in the PNG folder, or <FILE>.csv beside the video
  std::unique_ptr<VideoWriter> video_;  // null when writing PNGs
  std::ofstream csv_;
};

}  // namespace slamcmp
