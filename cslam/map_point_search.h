#pragma once
// Map points found again: a map point whose feature is no longer tracked (it left the image, or
// the camera turned away and back) is looked for where the current pose projects it, by normalised
// cross-correlation of the patch kept from its last keyframe, then aligned to sub-pixel by
// Lucas-Kanade. Found, it is tracked again under its old id, so the map it already has (placed
// while the board anchored it, perhaps) poses the frame at once: when the board returns after a
// gap its surroundings are known again in the same frame.
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "core/geometry.h"
#include "tracking/feature_tracker.h"

namespace slamcmp {

struct MapPointSearchOptions {
  bool enabled = true;               // combined mode: look for map points no longer tracked
  int radius_px = 6;                 // searched this far around the projection
  double min_ncc = 0.85;             // accepted at or above this correlation
  double min_patch_stddev = 10;      // grey levels; flatter patches are not searched
  double max_view_angle_deg = 25;    // the patch's view and the current one this far apart at most
  double max_distance_ratio = 1.3;   // nor this much nearer or farther
  int max_per_frame = 60;            // searched at most (the best-established points first)
  int below_map_points = 60;         // searched only while fewer map points than this are tracked
  template <class V>
  void visit(V& v) {
    v("enabled", enabled, "combined mode: look for map points no longer tracked where the pose projects them");
    v("radius_px", radius_px, "search radius around the projection, pixels");
    v("min_ncc", min_ncc, "normalised cross-correlation accepted at or above this");
    v("min_patch_stddev", min_patch_stddev, "grey levels; flatter patches are not searched");
    v("max_view_angle_deg", max_view_angle_deg,
      "a point is searched when the current view of it and its patch's view are this close, degrees");
    v("max_distance_ratio", max_distance_ratio,
      "a point is searched when the camera is within this ratio of the distance its patch was taken from");
    v("max_per_frame", max_per_frame, "points searched in one frame at most");
    v("below_map_points", below_map_points,
      "the search runs only while fewer map points than this are tracked (e.g. the board back after a gap)");
  }
  void check() const;
};

// The side of the patches kept for the search (pixels; its centre is the feature).
constexpr int kMapPatchSize = 21;

// A map point to look for: its position, its patch (kMapPatchSize square, CV_8U, taken at the
// feature's sub-pixel position) and the camera centre it was taken from.
struct MapPointCandidate {
  int id = 0;
  Vec3 p_world;
  const cv::Mat* patch = nullptr;
  Vec3 seen_from;
  int observations = 0;  // keyframes that saw it
};

// The patch of kMapPatchSize around uv (distorted pixels) in grey.
cv::Mat mapPointPatch(const cv::Mat& grey, const cv::Point2f& uv);

// Candidates found in grey near where T_world_camera projects them, as features with their old
// ids (distorted pixels). None closer than min_distance_px to an existing feature or to each
// other.
std::vector<Feature> searchMapPoints(const cv::Mat& grey, const CameraModel& camera, const SE3& T_world_camera,
                                     std::vector<MapPointCandidate> candidates, const std::vector<Feature>& existing,
                                     double min_distance_px, const MapPointSearchOptions& options);

}  // namespace slamcmp
