#include "core/frame_overlay.h"

namespace slamcmp {

const char* toString(OverlayFeatureState state) {
  switch (state) {
    case OverlayFeatureState::Inlier: return "inlier";
    case OverlayFeatureState::Rejected: return "rejected";
    case OverlayFeatureState::Matched: return "matched";
    case OverlayFeatureState::Failed: return "failed";
    case OverlayFeatureState::Unmeasured: return "unmeasured";
    case OverlayFeatureState::Initialising: return "initialising";
  }
  return "inlier";
}

std::vector<OverlayBoardCorner> wholeBoardCorners(const std::vector<Vec2>& uv) {
  std::vector<OverlayBoardCorner> corners;
  corners.reserve(uv.size());
  for (size_t k = 0; k < uv.size(); ++k) corners.push_back({static_cast<int>(k), uv[k]});
  return corners;
}

std::vector<Vec2> boardAxes(const CameraModel& camera, double square_size, const SE3& T_world_camera) {
  std::vector<Vec2> axes;
  if (!(square_size > 0)) return axes;  // no board (a board-free run)
  const SE3 T_camera_world = T_world_camera.inverse();
  const double axis = 1.5 * square_size;
  for (const Vec3& p_world : {Vec3(0, 0, 0), Vec3(axis, 0, 0), Vec3(0, axis, 0), Vec3(0, 0, axis)}) {
    const Vec3 p_camera = T_camera_world * p_world;
    if (p_camera.z() <= 0) return {};
    axes.push_back(camera.project(p_camera));
  }
  return axes;
}

}  // namespace slamcmp
