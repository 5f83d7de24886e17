#include "core/tracker.h"

namespace slamcmp {

const char* toString(TrackStatus status) {
  switch (status) {
    case TrackStatus::Board: return "board";
    case TrackStatus::TwoView: return "two_view";
    case TrackStatus::Ekf: return "ekf";
    case TrackStatus::Initialising: return "initialising";
    case TrackStatus::Lost: return "lost";
  }
  return "lost";
}

}  // namespace slamcmp
