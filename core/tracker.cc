#include "core/tracker.h"

namespace slamcmp {

const char* toString(TrackStatus status) {
  switch (status) {
    case TrackStatus::Tracked: return "tracked";
    case TrackStatus::Initialising: return "initialising";
    case TrackStatus::Lost: return "lost";
  }
  return "lost";
}

std::string statusLabel(TrackStatus status, const std::string& source) {
  return status == TrackStatus::Tracked ? source : toString(status);
}

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

}  // namespace slamcmp
