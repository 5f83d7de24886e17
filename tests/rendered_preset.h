#pragma once
// A synthetic preset's first frames rendered for a test suite, each with its true pose.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/geometry.h"
#include "core/target.h"

namespace slamcmp::test {

struct PosedFrame {
  cv::Mat grey;
  SE3 T_world_camera;  // ground truth
};

struct RenderedPreset {
  CameraModel camera;
  ChessboardTarget target;
  std::vector<PosedFrame> frames;
};

// The first `frames` (> 0) frames of `preset` (seed 1, the default anti-aliasing, as the accuracy
// tests render them), rendered in a temporary folder that is removed again.
RenderedPreset renderPreset(const std::string& preset, int frames);

}  // namespace slamcmp::test
