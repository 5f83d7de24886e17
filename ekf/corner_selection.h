#pragma once
// Where a new feature starts (Davison et al. 2007, section 3.6): the strongest Shi-Tomasi corner in
// an image box that holds no feature yet.
#include <functional>
#include <optional>
#include <random>
#include <vector>

#include <opencv2/core.hpp>

#include "core/geometry.h"
#include "ekf/ekf_options.h"

namespace slamcmp {

// Tries boxes of box_width x box_height at random positions (rng: reproducible runs), at least
// `margin` pixels from the border, keeps the first that contains none of `occupied` (feature
// pixels, with a half-box clearance around the box), and returns its strongest corner if its
// minimum eigenvalue reaches min_corner_eigenvalue. With `preferred` given, each free box's four
// strongest corners are tried in turn, those that are not `usable` (if given) skipped, and the
// first preferred one is returned; failing that, the first usable one met. False if no free box
// had a (usable) corner.
bool findCornerInFreeBox(const cv::Mat& grey, const std::vector<Vec2>& occupied,
                         const FeatureInitOptions& options, int margin, std::mt19937& rng, Vec2* uv,
                         const std::function<bool(const Vec2&)>& preferred = nullptr,
                         const std::function<bool(const Vec2&)>& usable = nullptr);

// The patch_size square centred on the pixel nearest uv; none if it leaves the image.
std::optional<cv::Rect> patchAround(const cv::Mat& grey, const Vec2& uv, int patch_size);

// Whether the patch_size template at uv has no look-alike in the square window of half-side
// `radius` pixels around it: no place there, apart from the connected peak around uv itself,
// correlates with it (normalised) at min_ncc or more, where the active search would accept it. A
// chessboard's corners repeat a square away diagonally; a feature placed on one is matched a
// square off in the first, widest searches of a board-free start. False if the template leaves
// the image.
bool hasNoLookAlike(const cv::Mat& grey, const Vec2& uv, int patch_size, int radius, double min_ncc);

}  // namespace slamcmp
