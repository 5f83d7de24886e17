#pragma once
// How wide an edge looks across itself: the spread (second moment, pixels^2) of the grey level's
// derivative along `normal` over [-half_length, half_length] about `at`. A step through the
// optics' blur (Gaussian, sigma) spreads by sigma^2 (plus the sampling's own, a constant); smeared
// by motion over L pixels along the normal, by L^2 / 12 more (a box's variance): how an edge
// shows the camera's exposure (hybrid/exposure_shift.h).
#include <optional>

#include <opencv2/core.hpp>

#include "core/geometry.h"

namespace slamcmp {

// Nothing when the profile leaves the image or holds no step (its derivative sums to under
// min_step grey levels).
std::optional<double> edgeSpread(const cv::Mat& grey, const Vec2& at, const Vec2& normal, double half_length,
                                 double min_step = 20);

}  // namespace slamcmp
