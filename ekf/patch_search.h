#pragma once
// Active search (SPEC section 5): the template correlated exhaustively over the pixels of a
// 3-sigma innovation ellipse (or the union of several, for a ray's depth particles).
#include <vector>

#include <opencv2/core.hpp>

#include "core/geometry.h"

namespace slamcmp {

struct SearchEllipse {
  Vec2 centre;  // predicted pixel
  Mat2 S;       // innovation covariance, pixels^2
};

struct PatchMatch {
  Vec2 uv;           // sub-pixel position of the best correlation
  double ncc = -1;   // its normalised cross-correlation
};

// Pixel box (inclusive bounds) holding every ellipse at `gate` standard deviations.
cv::Rect ellipsesBoundingBox(const std::vector<SearchEllipse>& ellipses, double gate);

// Correlates `templ` (odd square, CV_32F) at every integer pixel of the ellipses' bounding box
// whose template fits in the image (cv::matchTemplate, TM_CCOEFF_NORMED: correlation by DFT for
// large boxes, window means and energies from integral images), keeps the pixels inside at least
// one ellipse, and returns every local maximum scoring >= min_ncc, best first, each refined to
// sub-pixel by a parabola through its neighbours' scores. All are returned because a repetitive
// texture (the chessboard) gives several equally good peaks; the caller chooses among them.
std::vector<PatchMatch> searchEllipses(const cv::Mat& grey, const cv::Mat& templ,
                                       const std::vector<SearchEllipse>& ellipses, double gate,
                                       double min_ncc);

}  // namespace slamcmp
