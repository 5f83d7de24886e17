#pragma once
// The camera's orientation from two-view geometry to each of the last few frames (the thesis's
// section 3.3 over n views): each earlier frame's orientation composed with the rotation of the
// two-view motion from it (estimated with its translation), averaged. On tum_fr1_rpy (hand-held,
// turning about a point 8 cm behind the camera) a rotation fitted with the translation turns as
// the ground truth does, where a filter that cannot yet see the parallax, or a rotation fitted
// alone, turns 5-7 % too far (docs/findings.md, sessions 31 and 32).
// Pose direction: R_world_camera (p_world = R p_camera), as the EKF's state.
#include <deque>
#include <optional>
#include <utility>
#include <vector>

#include "core/geometry.h"

namespace slamcmp {

struct MultiBaselineRotationOptions {
  int max_gap = 10;            // views 1, 2, ..., max_gap frames back
  int min_shared = 20;         // tracks two views must share
  int refine_iterations = 10;  // Levenberg-Marquardt iterations on the Sampson distances, from each start
  double max_error_px = 1.0;   // the Cauchy loss's scale on the Sampson distances, pixels
  // A motion whose rotation is this far from the rotation fitted to the same tracks alone is taken
  // for a wrong solution (the twisted pair, a wrong valley), and the fitted rotation is used.
  double max_rotation_disagreement_deg = 5.0;
  // Views whose composed orientation is this far from the views' mean are left out of it.
  double max_spread_deg = 2.0;
  template <class V>
  void visit(V& v) {
    v("max_gap", max_gap, "an orientation is composed from each of the views up to this many frames back");
    v("min_shared", min_shared, "tracks two views must share");
    v("refine_iterations", refine_iterations,
      "Levenberg-Marquardt iterations on the Sampson distances from each start");
    v("max_error_px", max_error_px,
      "pixels, the scale of the Cauchy loss on the tracks' Sampson distances to the two-view motion");
    v("max_rotation_disagreement_deg", max_rotation_disagreement_deg,
      "degrees; a two-view rotation this far from the tracks' rotation-only fit is replaced by the fit");
    v("max_spread_deg", max_spread_deg,
      "degrees; views whose composed orientation is this far from the mean are left out");
  }
  void check() const;
};

// One frame's tracks: (track id, undistorted normalised coordinates), sorted by id (as a
// FeatureTracker holds them: ids grow as tracks start). Unsorted ones are refused
// (std::invalid_argument).
using FrameTracks = std::vector<std::pair<int, Vec2>>;

class MultiBaselineRotation {
 public:
  // focal_px (> 0) converts max_error_px to normalised units.
  MultiBaselineRotation(const MultiBaselineRotationOptions& options, double focal_px);

  // This frame's R_world_camera from the remembered frames up to max_gap back; nullopt if no view
  // shares enough tracks. *views: how many were averaged.
  std::optional<Mat3> measure(const FrameTracks& tracks, int* views = nullptr) const;
  // The frame just measured, with its orientation (the filter's, after its update), for later frames.
  void remember(FrameTracks tracks, const Mat3& R_world_camera);
  void clear() { frames_.clear(); }

 private:
  struct View {
    FrameTracks tracks;  // sorted by id
    Mat3 R_world_camera;
  };
  // R_b_a (p_b = R p_a) between an earlier view and the current tracks; nullopt if too few are
  // shared.
  std::optional<Mat3> relativeRotation(const FrameTracks& a, const FrameTracks& b) const;

  MultiBaselineRotationOptions options_;
  double focal_px_;
  std::deque<View> frames_;  // front: the last frame
};

// The rotation R (p_b = R p_a) best aligning unit bearings a[i] to b[i] (Kabsch).
Mat3 rotationOnlyFit(const std::vector<Vec3>& bearings_a, const std::vector<Vec3>& bearings_b);

}  // namespace slamcmp
