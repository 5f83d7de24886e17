#pragma once
// Deterministic clutter textures for the synthetic room: random shapes at several scales plus fine
// grain, so that Shi-Tomasi finds corners everywhere and every 11x11 patch is distinctive.
#include <cstdint>

#include <opencv2/core.hpp>

namespace slamcmp {

// A CV_8U albedo image of size_u x size_v metres at `texel` metres per texel, the same for the
// same seed.
cv::Mat makeClutterTexture(double size_u, double size_v, double texel, std::uint64_t seed);

}  // namespace slamcmp
