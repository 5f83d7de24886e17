#pragma once
// Whether an EKF back-end reports this frame's pose or calls the frame lost (SPEC section 4: never
// a made-up pose): a frame that measured nothing, a filter that has measured too little for several
// frames, whose camera position has grown too uncertain, or whose matches jump far beyond the run's
// own innovation level (a mismatch moved it), is extrapolating, not tracking. Its frames stay lost until
// something absolute anchors it again (hybrid: the board's corners; monoslam: a restart from the
// board, or a board-free map's relocalisation): new features mapped from a drifted pose agree
// with it, and would shrink its covariance around the wrong place.
#include <deque>
#include <string>

#include "ekf/ekf_options.h"
#include "ekf/ekf_state.h"

namespace slamcmp {

class PoseReporting {
 public:
  explicit PoseReporting(const ReportingOptions& options) : options_(options) {}
  // Why this frame's pose is not reported ("" if it is), given its measurements (points and board
  // corners), the joint NIS of its matched map features and its dof (FrameMeasurement; dof 0 where
  // none was computed), whether something absolute anchored it in this frame (the board; for a
  // board-free map, its own features found again), and the filter after its update.
  std::string weakness(int measured, double nis, int nis_dof, bool anchored, const EkfState& state);
  // The filter (re)started: nothing of the run before counts.
  void reset() {
    weak_frames_ = 0;
    lost_.clear();
    nis_per_dof_.clear();
  }

 private:
  // Why the innovations are out of line with the run's own level ("" if they are not, or if not
  // `test`ed); keeps this frame's in the history.
  std::string innovationJump(double nis, int nis_dof, bool test);

  ReportingOptions options_;
  int weak_frames_ = 0;
  std::string lost_;  // why the frames are lost until the next anchor; "" while tracking
  std::deque<double> nis_per_dof_;  // the last innovation_window frames' with matches
};

}  // namespace slamcmp
