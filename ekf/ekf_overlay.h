#pragma once
// What an EKF back-end saw in a frame (core/frame_overlay.h), for `run --overlay / --show`.
#include <vector>

#include "core/camera.h"
#include "core/frame_overlay.h"
#include "core/target.h"
#include "ekf/ekf_state.h"
#include "ekf/frame_measurement.h"
#include "ekf/map_feature.h"

namespace slamcmp {

// Every visible point of `measurement` as Matched (at its match), Failed or Unmeasured (at its
// prior prediction), with the search ellipse (S, pixels^2) of each searched one; every ray as
// Initialising at its projection at the particles' mean depth, and its particles projected,
// nearest first; the board axes projected from the state's pose. `state` is the filter after the
// frame's update (rays and axes use it; the points' pixels are those the search used); call it
// before features are added or removed, since `measurement` indexes `features`.
FrameOverlay ekfOverlay(const EkfState& state, const std::vector<MapFeature>& features,
                             const FrameMeasurement& measurement, const CameraModel& camera,
                             const ChessboardTarget& target, int patch_size);

}  // namespace slamcmp
