#include "ekf/ekf_options.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

namespace slamcmp {

namespace {

void require(bool ok, const std::string& field, const std::string& what) {
  if (!ok) throw OptionError(field, what);
}

}  // namespace

void MotionModelOptions::check() const {
  require(sigma_a > 0, "sigma_a", "must be positive, got " + std::to_string(sigma_a));
  require(sigma_alpha > 0, "sigma_alpha", "must be positive, got " + std::to_string(sigma_alpha));
  require(reference_rate > 0, "reference_rate", "must be positive");
  require(default_dt > 0, "default_dt", "must be positive, got " + std::to_string(default_dt));
  // The floors are the least the adapted noise takes, the set values the most.
  require(!adaptive.enabled || adaptive.min_sigma_a <= sigma_a, "adaptive.min_sigma_a",
          "must not exceed sigma_a (" + std::to_string(sigma_a) + "), got " + std::to_string(adaptive.min_sigma_a));
  require(!adaptive.enabled || adaptive.min_sigma_alpha <= sigma_alpha, "adaptive.min_sigma_alpha",
          "must not exceed sigma_alpha (" + std::to_string(sigma_alpha) + "), got " +
              std::to_string(adaptive.min_sigma_alpha));
}

void AdaptiveMotionOptions::check() const {
  require(time_constant > 0, "time_constant", "must be positive (s), got " + std::to_string(time_constant));
  require(min_sigma_a > 0, "min_sigma_a", "must be positive, got " + std::to_string(min_sigma_a));
  require(min_sigma_alpha > 0, "min_sigma_alpha", "must be positive, got " + std::to_string(min_sigma_alpha));
}

void ActiveSearchOptions::check() const {
  require(patch_size >= 3 && patch_size % 2 == 1, "patch_size",
          "must be odd and at least 3, got " + std::to_string(patch_size));
  require(sigma_gate > 0, "sigma_gate", "must be positive");
  require(min_ncc > -1 && min_ncc <= 1, "min_ncc", "must be in (-1, 1]");
  require(min_patch_stddev >= 0, "min_patch_stddev", "must not be negative");
  require(pixel_sigma > 0, "pixel_sigma", "must be positive");
  require(features_per_frame >= 1, "features_per_frame", "must be at least 1");
  require(max_search_half_axis > 0, "max_search_half_axis", "must be positive");
  require(max_candidates >= 1, "max_candidates", "must be at least 1");
  require(joint_gate > 0 && joint_gate < 1, "joint_gate", "must be in (0, 1)");
  require(consistency_gate > 0 && consistency_gate < 1, "consistency_gate", "must be in (0, 1)");
  require(min_variance_factor >= 0 && min_variance_factor <= 1, "min_variance_factor", "must be in [0, 1]");
  require(consistency_core_min == 0 || consistency_core_min >= 4, "consistency_core_min", "must be 0 or at least 4");
  require(source_size >= patch_size && source_size % 2 == 1, "source_size",
          "must be odd and at least patch_size, got " + std::to_string(source_size));
  require(rolling_shutter_readout >= 0 && rolling_shutter_readout <= 1, "rolling_shutter_readout",
          "must be in [0, 1] seconds");
}

void ActiveSearchOptions::checkImage(cv::Size image) const {
  requireWithinImage("source_size", source_size, std::min(image.width, image.height), image);
}

namespace {

// An option resolved by usesOption: "auto" follows the start (on without a board).
void requireUse(const std::string& field, const std::string& use) {
  require(use == "auto" || use == "on" || use == "off", field, "must be auto, on or off, got '" + use + "'");
}

}  // namespace

void FeatureInitOptions::check() const {
  // Each initialising ray holds and weighs all of them every frame.
  require(particles >= 2 && particles <= 100000, "particles", "must be in [2, 100000]");
  require(min_depth > 0 && max_depth > min_depth, "min_depth",
          "need 0 < min_depth < max_depth");
  require(promote_ratio > 0, "promote_ratio", "must be positive");
  require(min_particles >= 1 && min_particles <= particles, "min_particles",
          "must be in [1, particles]");
  require(prune_threshold >= 0 && prune_threshold < 1, "prune_threshold",
          "must be in [0, 1)");
  require(max_frames >= 1, "max_frames", "must be at least 1");
  require(max_initialising >= 0, "max_initialising", "must not be negative");
  require(min_visible >= 0, "min_visible", "must not be negative");
  require(box_width >= 16 && box_height >= 16, "box_width", "boxes must be at least 16x16");
  require(min_corner_eigenvalue >= 0, "min_corner_eigenvalue", "must not be negative");
  requireUse("distinct", distinct);
  require(distinct_radius >= 1 && distinct_radius <= 1000, "distinct_radius", "must be in [1, 1000] pixels");
}

void FeatureInitOptions::checkImage(cv::Size image) const {
  requireWithinImage("box_width", box_width, image.width, image);
  requireWithinImage("box_height", box_height, image.height, image);
}

void MapManagementOptions::check() const {
  require(max_features >= 1, "max_features", "must be at least 1");
  require(min_attempts >= 1, "min_attempts", "must be at least 1");
  require(min_success_ratio >= 0 && min_success_ratio <= 1, "min_success_ratio", "must be in [0, 1]");
  require(max_misses_in_a_row >= 0, "max_misses_in_a_row", "must not be negative");
}

void HealthOptions::check() const {
  require(max_frames_unmeasured >= 1, "max_frames_unmeasured", "must be at least 1");
  require(max_speed > 0, "max_speed", "must be positive");
  require(max_angular_speed > 0, "max_angular_speed", "must be positive");
  require(max_position_sigma > 0, "max_position_sigma", "must be positive");
}

void StartOptions::check() const {
  for (const auto& [field, sigma] : {std::pair{"position_sigma", position_sigma},
                                      {"orientation_sigma", orientation_sigma},
                                      {"manual_position_sigma", manual_position_sigma},
                                      {"manual_orientation_sigma", manual_orientation_sigma},
                                      {"velocity_sigma", velocity_sigma},
                                      {"angular_velocity_sigma", angular_velocity_sigma},
                                      {"restart_move_per_frame", restart_move_per_frame},
                                      {"restart_turn_per_frame", restart_turn_per_frame},
                                      {"board_free_turn_per_frame", board_free_turn_per_frame},
                                      {"board_free_move_per_frame", board_free_move_per_frame}})
    require(sigma >= 0 && std::isfinite(sigma), field, "must be a finite standard deviation >= 0");
}

void ReportingOptions::check() const {
  require(min_measured >= 0, "min_measured", "must be >= 0");
  require(max_weak_frames >= 1, "max_weak_frames", "must be >= 1");
  require(max_position_sigma > 0, "max_position_sigma", "must be positive");
  require(max_innovation_jump == 0 || (max_innovation_jump > 1 && std::isfinite(max_innovation_jump)),
          "max_innovation_jump", "must be 0 (off) or a finite factor above 1");
  require(innovation_window >= kMinInnovationHistory, "innovation_window",
          "must be at least " + std::to_string(kMinInnovationHistory) + " (the frames the check waits for)");
}

// Board-free start (issue 18).

void InverseDepthOptions::check() const {
  requireUse("use", use);
  require(rho0 > 0, "rho0", "must be positive");
  require(rho_sigma > 0, "rho_sigma", "must be positive");
  require(scale_gauge_sigma >= 0, "scale_gauge_sigma", "must be >= 0");
  require(linearity_threshold > 0, "linearity_threshold", "must be positive");
  require(new_per_frame >= 1, "new_per_frame", "must be at least 1");
}

void OnePointRansacOptions::check() const {
  requireUse("use", use);
  require(inlier_pixels > 0, "inlier_pixels", "must be positive");
  require(probability > 0 && probability < 1, "probability", "must be in (0, 1)");
  require(max_hypotheses >= 1, "max_hypotheses", "must be at least 1");
  require(rescue_gate > 0 && rescue_gate < 1, "rescue_gate", "must be in (0, 1)");
  require(max_turn_sigma > 0, "max_turn_sigma", "must be positive");
}

void RelocalisationOptions::check() const {
  require(interval >= 1 && interval <= 1000, "interval", "must be in [1, 1000] frames");
  require(frame_corners >= 10 && frame_corners <= 100000, "frame_corners", "must be in [10, 100000]");
  require(ratio > 0 && ratio <= 1, "ratio", "must be in (0, 1]");
  require(min_inliers >= 4 && min_inliers <= 10000, "min_inliers", "must be in [4, 10000] (a pose needs four points)");
  require(min_inlier_ratio >= 0 && min_inlier_ratio <= 1, "min_inlier_ratio", "must be in [0, 1]");
  require(max_error_px > 0 && max_error_px <= 100, "max_error_px", "must be in (0, 100] pixels");
  require(position_sigma > 0 && position_sigma < 100, "position_sigma", "must be in (0, 100)");
  require(orientation_sigma > 0 && orientation_sigma < 1, "orientation_sigma", "must be in (0, 1)");
  require(guided_radius_px >= 0 && guided_radius_px <= 10000, "guided_radius_px", "must be in [0, 10000] pixels");
  require(guided_max_hamming >= 0 && guided_max_hamming <= 256, "guided_max_hamming", "must be in [0, 256]");
  require(retired_points >= 0 && retired_points <= 100000, "retired_points", "must be in [0, 100000]");
}

bool usesOption(const std::string& use, bool board_free) { return use == "on" || (use == "auto" && board_free); }

}  // namespace slamcmp
