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

}  // namespace slamcmp
