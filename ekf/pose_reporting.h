#pragma once
// Whether an EKF back-end reports this frame's pose or calls the frame lost (SPEC section 4: never
// a made-up pose): a filter that has measured too little for several frames, or whose camera
// position has grown too uncertain, is extrapolating, not tracking. The filter itself runs on, but
// its frames stay lost until something absolute anchors it again (the board, or a restart): new
// features mapped from a drifted pose agree with it, and would shrink its covariance around the
// wrong place.
#include <string>

#include "ekf/ekf_options.h"
#include "ekf/ekf_state.h"

namespace slamcmp {

class PoseReporting {
 public:
  explicit PoseReporting(const ReportingOptions& options) : options_(options) {}
  // Why this frame's pose is not reported ("" if it is), given its measurements (points and board
  // corners), whether the board anchored it in this frame, and the filter after its update.
  std::string weakness(int measured, bool anchored, const EkfState& state);
  void reset() {
    weak_frames_ = 0;
    lost_.clear();
  }

 private:
  ReportingOptions options_;
  int weak_frames_ = 0;
  std::string lost_;  // why the frames are lost until the next anchor; "" while tracking
};

}  // namespace slamcmp
