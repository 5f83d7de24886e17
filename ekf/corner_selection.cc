#include "ekf/corner_selection.h"

#include <optional>

#include <opencv2/imgproc.hpp>

namespace slamcmp {

namespace {

constexpr int kCornersPerBox = 4;
constexpr int kCornerSeparationPx = 5;  // corners of one box tried apart by at least this

}  // namespace

bool findCornerInFreeBox(const cv::Mat& grey, const std::vector<Vec2>& occupied,
                         const FeatureInitOptions& options, int margin, std::mt19937& rng, Vec2* uv,
                         const std::function<bool(const Vec2&)>& preferred,
                         const std::function<bool(const Vec2&)>& usable) {
  const int w = options.box_width, h = options.box_height;
  const int max_x = grey.cols - margin - w, max_y = grey.rows - margin - h;
  if (max_x < margin || max_y < margin) return false;
  std::uniform_int_distribution<int> ux(margin, max_x), uy(margin, max_y);
  constexpr int kTries = 10;
  std::optional<Vec2> fallback;  // the first usable corner met, when none is preferred
  for (int attempt = 0; attempt < kTries; ++attempt) {
    const cv::Rect box(ux(rng), uy(rng), w, h);
    bool free = true;
    for (const Vec2& p : occupied) {
      if (p.x() > box.x - w / 2 && p.x() < box.x + w + w / 2 && p.y() > box.y - h / 2 &&
          p.y() < box.y + h + h / 2) {
        free = false;
        break;
      }
    }
    if (!free) continue;
    cv::Mat eig;
    cv::cornerMinEigenVal(grey(box), eig, 3);
    for (int k = 0; k < (preferred ? kCornersPerBox : 1); ++k) {
      double best;
      cv::Point where;
      cv::minMaxLoc(eig, nullptr, &best, nullptr, &where);
      if (best < options.min_corner_eigenvalue) break;
      const Vec2 corner(box.x + where.x, box.y + where.y);
      if (!preferred) {
        *uv = corner;
        return true;
      }
      if (!usable || usable(corner)) {
        if (preferred(corner)) {
          *uv = corner;
          return true;
        }
        if (!fallback) fallback = corner;
      }
      cv::circle(eig, where, kCornerSeparationPx, cv::Scalar(0), cv::FILLED);
    }
  }
  if (fallback) *uv = *fallback;
  return fallback.has_value();
}

std::optional<cv::Rect> patchAround(const cv::Mat& grey, const Vec2& uv, int patch_size) {
  const int half = patch_size / 2;
  const cv::Rect patch(static_cast<int>(std::lround(uv.x())) - half, static_cast<int>(std::lround(uv.y())) - half,
                       patch_size, patch_size);
  if ((patch & cv::Rect(0, 0, grey.cols, grey.rows)) != patch) return std::nullopt;
  return patch;
}

bool hasNoLookAlike(const cv::Mat& grey, const Vec2& uv, int patch_size, int radius, double min_ncc) {
  const std::optional<cv::Rect> patch = patchAround(grey, uv, patch_size);
  if (!patch) return false;
  const cv::Rect region = cv::Rect(patch->x - radius, patch->y - radius, patch_size + 2 * radius,
                                   patch_size + 2 * radius) & cv::Rect(0, 0, grey.cols, grey.rows);
  cv::Mat ncc;
  cv::matchTemplate(grey(region), grey(*patch), ncc, cv::TM_CCOEFF_NORMED);
  // The places that would be accepted, less the connected peak the patch itself sits in.
  cv::Mat accepted = ncc >= min_ncc;
  cv::floodFill(accepted, cv::Point(patch->x - region.x, patch->y - region.y), cv::Scalar(0));
  return cv::countNonZero(accepted) == 0;
}

}  // namespace slamcmp
