#pragma once
// The constant-velocity model's impulse noise estimated from the filter's own velocity corrections
// (covariance matching: Mohamed and Schwarz, "Adaptive Kalman filtering for INS/GPS", J. Geodesy
// 1999, eq. 30). The velocity block propagates as v' = v + V, so between two posteriors
//   Q_v = E[(v_k - v_{k-1})(v_k - v_{k-1})^T] + P_vv,k - P_vv,k-1,
// which equals the Q the filter used when its innovations are as large as it predicts and moves
// towards the camera's real accelerations when they are not (larger when the filter lags, smaller
// when it over-smooths). The same for the angular velocity. One variance per block (the mean of
// its three axes), as sigma_a and sigma_alpha, averaged with a time constant and kept between
// the options' floors and their set values.
#include "ekf/ekf_options.h"
#include "ekf/ekf_state.h"

namespace slamcmp {

class AdaptiveMotionNoise {
 public:
  explicit AdaptiveMotionNoise(const MotionModelOptions& options);

  // The motion options for the next prediction, over dt seconds from `posterior` (the state at
  // the end of the last frame); the set ones when not enabled.
  const MotionModelOptions& next(const EkfState& posterior, double dt);
  // A new start (the state was reset or moved): back to the set noise, the corrections forgotten.
  void restart() { *this = AdaptiveMotionNoise(set_); }
  const MotionModelOptions& current() const { return current_; }

 private:
  MotionModelOptions set_;
  MotionModelOptions current_;
  bool has_last_ = false;
  double last_dt_ = 0;
  Vec3 last_v_ = Vec3::Zero(), last_w_ = Vec3::Zero();
  double last_trace_v_ = 0, last_trace_w_ = 0;
  double mean_a2_, mean_alpha2_;  // running means of sigma_a^2 and sigma_alpha^2
};

}  // namespace slamcmp
