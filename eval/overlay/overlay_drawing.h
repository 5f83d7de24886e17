#pragma once
// Draws what a back-end saw in one frame (core/frame_overlay.h) onto a colour copy of the frame,
// with the frame number, timestamp, status and a legend: the pictures of `run --overlay` and
// `run --show`. Colours follow SceneLib for MonoSLAM (matched patches red, failed yellow).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/sequence.h"
#include "core/tracker.h"

namespace slamcmp {

// BGR colours of the drawing; tests look for them at the drawn positions.
namespace overlay_colour {
const cv::Scalar kBoardCorner(0, 0, 255);    // red
const cv::Scalar kAxisX(0, 0, 255);          // red
const cv::Scalar kAxisY(0, 255, 0);          // green
const cv::Scalar kAxisZ(255, 0, 0);          // blue
const cv::Scalar kInlier(0, 255, 0);         // cslam: green
const cv::Scalar kRejected(255, 0, 255);     // cslam: magenta
const cv::Scalar kMatched(0, 0, 255);        // monoslam patch and ellipse: red
const cv::Scalar kFailed(0, 255, 255);       // monoslam patch and ellipse: yellow
const cv::Scalar kUnmeasured(255, 255, 0);   // monoslam: cyan
const cv::Scalar kInitialising(0, 165, 255); // monoslam depth particles: orange
}  // namespace overlay_colour

// One drawn primitive, as overlay.csv lists it (frame,kind,id,u,v,state).
struct DrawnPrimitive {
  std::string kind;        // board_corner | board_axis | feature | ellipse | particle_line
  int id = -1;             // corner index | 0 origin, 1 x, 2 y, 3 z | feature id | line index
  Vec2 uv = Vec2::Zero();  // pixels (distorted, as in the frame): where it is drawn
  std::string state;       // detected | origin, x, y, z | the feature state | matched, failed | near, far
};

class OverlayDrawer {
 public:
  // A BGR copy of frame.grey with result.overlay drawn on it (when there is one), the frame number,
  // timestamp, status (and the reason when lost) and a legend of every kind of primitive drawn so
  // far in the run (so it does not flicker). `drawn` receives what was drawn, in drawing order.
  cv::Mat draw(const Frame& frame, const FrameResult& result, std::vector<DrawnPrimitive>* drawn = nullptr);

 private:
  unsigned legend_seen_ = 0;  // one bit per legend entry
};

}  // namespace slamcmp
