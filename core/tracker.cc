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

}  // namespace slamcmp
