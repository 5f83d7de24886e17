#pragma once
// One feature of the MonoSLAM map: a 3D point, a ray still being initialised (feature_ray.h) or a
// feature in inverse depth (inverse_depth.h), with its appearance and its match record.
#include <opencv2/core.hpp>

#include "ekf/feature_ray.h"
#include "ekf/patch_warp.h"

namespace slamcmp {

struct MapFeature {
  int id = 0;
  int offset = 0;        // state offset: 3 values for a point, 6 for a ray or an inverse-depth feature
  bool is_ray = false;   // initialising: ray plus depth particles
  bool inverse_depth = false;  // measured in inverse depth (inverse_depth.h) until converted to a point
  bool known = false;    // a board corner with zero uncertainty
  PatchSource source;
  cv::Mat ray_template;  // the unwarped first-view template, for the particle search
  DepthParticles particles;
  int ray_frames = 0;
  int attempts = 0, successes = 0;
  int misses_in_a_row = 0;  // attempts since its last match
  cv::Mat descriptor;    // ORB of its first view, for relocalisation (ekf/relocaliser.h); empty if none
  int dim() const { return is_ray || inverse_depth ? 6 : 3; }  // its block in the state
};

}  // namespace slamcmp
