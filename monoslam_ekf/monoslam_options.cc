#include "monoslam_ekf/monoslam_options.h"

#include <string>

namespace slamcmp {

namespace {

void require(bool ok, const std::string& field, const std::string& what) {
  if (!ok) throw InputError("monoslam." + field, what);
}

}  // namespace

void MotionModelOptions::check() const {
  require(sigma_a > 0, "motion.sigma_a", "must be positive, got " + std::to_string(sigma_a));
  require(sigma_alpha > 0, "motion.sigma_alpha", "must be positive, got " + std::to_string(sigma_alpha));
  require(reference_rate > 0, "motion.reference_rate", "must be positive");
  require(default_dt > 0, "motion.default_dt", "must be positive, got " + std::to_string(default_dt));
}

void ActiveSearchOptions::check() const {
  require(patch_size >= 3 && patch_size % 2 == 1, "search.patch_size",
          "must be odd and at least 3, got " + std::to_string(patch_size));
  require(sigma_gate > 0, "search.sigma_gate", "must be positive");
  require(min_ncc > -1 && min_ncc <= 1, "search.min_ncc", "must be in (-1, 1]");
  require(min_patch_stddev >= 0, "search.min_patch_stddev", "must not be negative");
  require(pixel_sigma > 0, "search.pixel_sigma", "must be positive");
  require(features_per_frame >= 1, "search.features_per_frame", "must be at least 1");
  require(max_search_half_axis > 0, "search.max_search_half_axis", "must be positive");
  require(max_candidates >= 1, "search.max_candidates", "must be at least 1");
  require(joint_gate > 0 && joint_gate < 1, "search.joint_gate", "must be in (0, 1)");
  require(consistency_gate > 0 && consistency_gate < 1, "search.consistency_gate", "must be in (0, 1)");
  require(source_size >= patch_size && source_size % 2 == 1, "search.source_size",
          "must be odd and at least patch_size, got " + std::to_string(source_size));
}

void FeatureInitOptions::check() const {
  require(particles >= 2, "feature_init.particles", "must be at least 2");
  require(min_depth > 0 && max_depth > min_depth, "feature_init.min_depth",
          "need 0 < min_depth < max_depth");
  require(promote_ratio > 0, "feature_init.promote_ratio", "must be positive");
  require(min_particles >= 1 && min_particles <= particles, "feature_init.min_particles",
          "must be in [1, particles]");
  require(prune_threshold >= 0 && prune_threshold < 1, "feature_init.prune_threshold",
          "must be in [0, 1)");
  require(max_frames >= 1, "feature_init.max_frames", "must be at least 1");
  require(max_initialising >= 0, "feature_init.max_initialising", "must not be negative");
  require(min_visible >= 0, "feature_init.min_visible", "must not be negative");
  require(box_width >= 16 && box_height >= 16, "feature_init.box_width", "boxes must be at least 16x16");
  require(min_corner_eigenvalue >= 0, "feature_init.min_corner_eigenvalue", "must not be negative");
}

void MapManagementOptions::check() const {
  require(max_features >= 1, "map.max_features", "must be at least 1");
  require(min_attempts >= 1, "map.min_attempts", "must be at least 1");
  require(min_success_ratio >= 0 && min_success_ratio <= 1, "map.min_success_ratio", "must be in [0, 1]");
}

void HealthOptions::check() const {
  require(max_frames_unmeasured >= 1, "health.max_frames_unmeasured", "must be at least 1");
  require(max_speed > 0, "health.max_speed", "must be positive");
  require(max_angular_speed > 0, "health.max_angular_speed", "must be positive");
  require(max_position_sigma > 0, "health.max_position_sigma", "must be positive");
}

void StartOptions::check() const {
  require(position_sigma >= 0 && orientation_sigma >= 0 && manual_position_sigma >= 0 &&
              manual_orientation_sigma >= 0 && velocity_sigma >= 0 &&
              angular_velocity_sigma >= 0,
          "start", "standard deviations must not be negative");
}

void MonoslamOptions::check() const {
  motion.check();
  search.check();
  feature_init.check();
  map.check();
  health.check();
  start.check();
  board.check();
}

}  // namespace slamcmp
