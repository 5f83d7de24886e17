#pragma once
// A feature being initialised (Davison et al. 2007, section 3.6): a ray from the camera centre that
// first saw it, held in the EKF state as a 6-vector (origin r0, unit direction h) correlated with the
// camera, and a particle set over its depth. On convergence it becomes a 3D point y = r0 + d h.
#include <vector>

#include <opencv2/core.hpp>

#include "core/camera.h"
#include "ekf/ekf_state.h"
#include "ekf/ekf_options.h"

namespace slamcmp {

// Appends the ray through the distorted pixel uv from the current camera; its covariance comes from
// the camera's (r, q) and the pixel noise. Returns its state offset.
int appendRay(EkfState& state, const CameraModel& camera, const Vec2& uv_distorted, double pixel_sigma);

// Replaces the ray at ray_offset by the point r0 + depth h with depth ~ N(depth_mean, depth_var):
// P_y = J P_ray J^T + depth_var h h^T, J = [I, depth I], cross covariances J P_ray,rest. The ray's
// 6 rows are removed; the point is appended at the end. Returns the point's offset.
int promoteRay(EkfState& state, int ray_offset, double depth_mean, double depth_var);

struct DepthParticles {
  std::vector<double> depth;   // m along the ray
  std::vector<double> weight;  // normalised
  int size() const { return static_cast<int>(depth.size()); }
  double mean() const;
  double stddev() const;
};

// n particles uniform over [min_depth, max_depth], equal weights.
DepthParticles uniformParticles(int n, double min_depth, double max_depth);

// One frame of depth estimation: predicts each particle's pixel and innovation covariance from the
// state (camera and ray blocks), searches the union of their gated ellipses with the template,
// multiplies each weight by the Gaussian likelihood of the match, normalises and prunes those
// under prune_threshold times the best. False (weights unchanged) if nothing matched, or while the
// particles' ellipses span over a quarter of the image (the search waits for a smaller spread).
bool updateDepthParticles(const EkfState& state, int ray_offset, const CameraModel& camera,
                          const cv::Mat& grey, const cv::Mat& templ, const ActiveSearchOptions& search,
                          double prune_threshold, DepthParticles* particles);

}  // namespace slamcmp
