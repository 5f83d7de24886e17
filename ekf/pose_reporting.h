#pragma once
// Whether an EKF back-end reports this frame's pose or calls the frame lost (SPEC section 4: never
// a made-up pose): a filter that has measured too little for several frames, or whose camera
// position has grown too uncertain, is extrapolating, not tracking. The filter itself runs on.
#include <string>

#include "ekf/ekf_options.h"
#include "ekf/ekf_state.h"

namespace slamcmp {

class PoseReporting {
 public:
  explicit PoseReporting(const ReportingOptions& options) : options_(options) {}
  // Why this frame's pose is not reported ("" if it is), given its measurements (points and board
  // corners) and the filter after its update.
  std::string weakness(int measured, const EkfState& state);
  void reset() { weak_frames_ = 0; }

 private:
  ReportingOptions options_;
  int weak_frames_ = 0;
};

}  // namespace slamcmp
