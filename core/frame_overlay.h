#pragma once
// What a back-end saw in one frame, in image pixels (distorted, as in the frame), for drawing
// (`run --overlay`, `run --show`). Back-ends fill it only when TrackerContext::want_overlay is
// set, so runs that draw nothing pay nothing. Drawing lives in eval; this is only the data.
#include <vector>

#include "core/camera.h"
#include "core/geometry.h"

namespace slamcmp {

enum class OverlayFeatureState {
  Inlier,        // tracked frame to frame and consistent with the frame's motion
  Rejected,      // dropped this frame by a consistency check (forward-backward, epipolar)
  Matched,       // searched where the filter predicted it and matched (red, as SceneLib draws)
  Failed,        // searched and not matched (yellow)
  Unmeasured,    // in the map and predicted in view, not searched this frame
  Initialising,  // a depth hypothesis (ray) not yet a point
};
const char* toString(OverlayFeatureState state);

struct OverlayFeature {
  int id = -1;
  Vec2 uv = Vec2::Zero();
  OverlayFeatureState state = OverlayFeatureState::Inlier;
};

// The 3-sigma ellipse {x : (x - centre)^T S^-1 (x - centre) <= 9} of an innovation covariance S.
struct OverlayEllipse {
  int feature_id = -1;
  Vec2 centre = Vec2::Zero();
  Mat2 S = Mat2::Identity();  // pixels^2
  bool matched = false;
};

struct OverlayBoardCorner {
  int id = -1;  // the corner's index in the target (SPEC section 2): a part of the board keeps its corners' own
  Vec2 uv = Vec2::Zero();
};

// The corners of a whole board detected in the target's order: corner k is the target's k.
std::vector<OverlayBoardCorner> wholeBoardCorners(const std::vector<Vec2>& uv);

// FrameOverlay::board_axes for a camera at T_world_camera: the board's origin, then the ends of its
// x, y and z axes (1.5 squares long); none when an end is behind the camera, or without a board
// (square_size 0).
std::vector<Vec2> boardAxes(const CameraModel& camera, double square_size, const SE3& T_world_camera);

struct FrameOverlay {
  std::vector<OverlayBoardCorner> board_corners;  // the board corners detected; empty if none
  // Board axes projected: origin, then the ends of x, y and z (one and a half squares long).
  std::vector<Vec2> board_axes;
  std::vector<OverlayFeature> features;
  std::vector<OverlayEllipse> search_ellipses;
  int patch_size = 0;  // side of the matched/failed patches drawn at features (0: none)
  // Each initialising feature's depth particles projected into this frame, nearest first.
  std::vector<std::vector<Vec2>> particle_lines;
};

}  // namespace slamcmp
