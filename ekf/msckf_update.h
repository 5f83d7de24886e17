#pragma once
// The multi-state constraint update (Mourikis and Roumeliotis 2007, the MSCKF) of points tracked
// over a sliding window of past camera poses cloned into the state (stochastic cloning, Roumeliotis
// and Burdick 2002). A track's point is triangulated from the clones that saw it, its reprojection
// residuals are projected onto the left null space of their Jacobian with respect to the point (so
// the point itself never enters the state), and what is left constrains the clones' poses: their
// relative motion, its length included, at the scale the filter holds. Many features tracked by
// Lucas-Kanade then tie the window's poses together without growing the map.
#include <optional>
#include <vector>

#include "core/camera.h"
#include "ekf/ekf_state.h"

namespace slamcmp {

constexpr int kCloneDim = 7;  // a cloned camera pose: r, q
// The camera's (r, q) appended to the state's tail as a clone; returns its offset, which holds
// only until a map block is appended or removed in front of it: a caller keeps a clone's place
// from the end of the state (size() - tailSize()).
int cloneCameraPose(EkfState& state);

struct CloneObservation {
  int clone_offset = 0;  // the clone (state offset of its r, q) that saw the point
  Vec2 uv;               // where, distorted pixels
};

struct MsckfOptions {
  double pixel_sigma = 0.5;           // a tracked point's noise per coordinate, pixels
  double gate_probability = 0.99;     // a track's chi-squared test on its projected residual
  double min_parallax_deg = 0.5;      // between the track's first and last rays: less, no depth
  double max_triangulation_px = 2.0;  // a triangulated point's largest reprojection error
  // Each track tested against all the others and the prior (Baarda's data snooping,
  // ekf/data_snooping.h) at this probability, the worst dropped until none fails; 0: not tested.
  double snooping_probability = 0;
};

// The point that the clones' observations meet, by Gauss-Newton on the pixel residuals from the
// midpoint of the first and last rays; nullopt when the rays are closer than min_parallax_deg,
// the point is not in front of every clone, or it misses one by more than max_triangulation_px.
std::optional<Vec3> triangulateTrack(const EkfState& state, const CameraModel& camera,
                                     const std::vector<CloneObservation>& track, const MsckfOptions& options);

struct MsckfResult {
  int used = 0;       // tracks in the update
  int rejected = 0;   // tracks failing the gate
  int snooped = 0;    // tracks passing the gate but failing the test against the others
  int untriangulated = 0;
  bool applied = false;
};

// One update from all the tracks given (each of at least two observations in distinct clones).
// The stacked rows are compressed by a QR factorisation to the clones' columns when they are
// more, so the cost is linear in the tracks and quadratic in the state.
MsckfResult msckfUpdate(EkfState& state, const CameraModel& camera,
                        const std::vector<std::vector<CloneObservation>>& tracks, const MsckfOptions& options);

}  // namespace slamcmp
