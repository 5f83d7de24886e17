#pragma once
// Where a new feature starts (Davison et al. 2007, section 3.6): the strongest Shi-Tomasi corner in
// an image box that holds no feature yet.
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "core/geometry.h"
#include "ekf/ekf_options.h"

namespace slamcmp {

// Tries boxes of box_width x box_height at random positions (rng: reproducible runs), at least
// `margin` pixels from the border, keeps the first that contains none of `occupied` (feature
// pixels, with a half-box clearance around the box), and returns its strongest corner if its
// minimum eigenvalue reaches min_corner_eigenvalue. False if no free box had one.
bool findCornerInFreeBox(const cv::Mat& grey, const std::vector<Vec2>& occupied,
                         const FeatureInitOptions& options, int margin, std::mt19937& rng, Vec2* uv);

}  // namespace slamcmp
