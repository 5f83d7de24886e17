#include "ekf/corner_selection.h"

#include <opencv2/imgproc.hpp>

namespace slamcmp {

bool findCornerInFreeBox(const cv::Mat& grey, const std::vector<Vec2>& occupied,
                         const FeatureInitOptions& options, int margin, std::mt19937& rng, Vec2* uv) {
  const int w = options.box_width, h = options.box_height;
  const int max_x = grey.cols - margin - w, max_y = grey.rows - margin - h;
  if (max_x < margin || max_y < margin) return false;
  std::uniform_int_distribution<int> ux(margin, max_x), uy(margin, max_y);
  constexpr int kTries = 10;
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
    double best;
    cv::Point where;
    cv::minMaxLoc(eig, nullptr, &best, nullptr, &where);
    if (best < options.min_corner_eigenvalue) continue;
    *uv = Vec2(box.x + where.x, box.y + where.y);
    return true;
  }
  return false;
}

}  // namespace slamcmp
