#include "core/subpixel_corner.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "core/error.h"

namespace slamcmp {

void SubpixelCornerOptions::check() const {
  if (std::find(kMethods.begin(), kMethods.end(), method) == kMethods.end())
    throw OptionError("method", "must be gradient or opencv, got '" + method + "'");
  if (!(smoothing_sigma_px >= 0 && smoothing_sigma_px <= 5))
    throw OptionError("smoothing_sigma_px", "must be in [0, 5] pixels");
  if (max_iterations < 1) throw OptionError("max_iterations", "must be >= 1");
  if (!(epsilon_px > 0)) throw OptionError("epsilon_px", "must be positive");
}

namespace {

constexpr double kExtraRadiusOverHalfWindow = 0.7, kMaxExtraRadius = 3.0;  // pixels
constexpr double kMinDeterminantOverTrace2 = 0.01;

// One corner; false (and `corner` unchanged) when its window has no junction or leaves the image.
bool refineCorner(const cv::Mat& grey, int half, const SubpixelCornerOptions& options, cv::Point2f* corner) {
  // The weights reach about as far as cv::cornerSubPix's square window does along its diagonal
  // (at most 3 px beyond the circle inside it): with that inner circle (half + 0.5) the real
  // views' small windows (half 2-3 on Bouguet's images) hold too few pixels against the noise, and
  // corners ran off by pixels. Near the image's border the circle shrinks to what the image holds,
  // down to half + 0.5.
  const double border = std::min({corner->x, corner->y, grey.cols - 1 - corner->x, grey.rows - 1 - corner->y});
  if (!(border >= 0)) return false;  // off the image, or not a number
  const double radius = std::min(half + 0.5 + std::min(kExtraRadiusOverHalfWindow * half, kMaxExtraRadius),
                                 std::max(half + 0.5, border - 2.5));
  const double radius2 = radius * radius;
  const int reach = static_cast<int>(std::ceil(radius + 0.5));  // q is within half a pixel of the centre
  // A blur wide against the window leaves no junction to place (half window 3, before the radius
  // grew: 0.36 px RMS at 1.5 px against 0.021 at 0.75): at most half the window beyond 1.5 px.
  const double sigma = std::clamp(0.5 * (half - 1.5), 0.0, options.smoothing_sigma_px);
  // The window: one pixel beyond the weights (central differences), which must be in the image,
  // and the blur's support beyond that (OpenCV's float kernel reaches 4 sigma), cut by the image's
  // border (replicated there).
  const int core = reach + 1, extent = core + static_cast<int>(std::ceil(4 * sigma));
  const cv::Rect image(0, 0, grey.cols, grey.rows);
  double qx = corner->x, qy = corner->y;
  cv::Mat smooth;
  cv::Point origin;    // the smoothed window's top-left pixel in the image
  int cx = 0, cy = 0;  // the pixel the window is centred on
  bool have_window = false;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    const int ix = static_cast<int>(std::lround(qx)), iy = static_cast<int>(std::lround(qy));
    if (!have_window || ix != cx || iy != cy) {
      const cv::Rect needed(ix - core, iy - core, 2 * core + 1, 2 * core + 1);
      if ((needed & image) != needed) return false;
      const cv::Rect rect = cv::Rect(ix - extent, iy - extent, 2 * extent + 1, 2 * extent + 1) & image;
      grey(rect).convertTo(smooth, CV_32F);
      if (sigma > 0) cv::GaussianBlur(smooth, smooth, cv::Size(), sigma, sigma, cv::BORDER_REPLICATE);
      origin = rect.tl();
      cx = ix, cy = iy, have_window = true;
    }
    // sum_p w g g^T (p - q_new) = 0, i.e. A (q_new - q) = sum_p w g g^T (p - q), with the weights
    // (1 - r^2 / R^2)^2 of r = |p - q|.
    double a = 0, b = 0, c = 0, rx = 0, ry = 0;
    for (int dv = -reach; dv <= reach; ++dv) {
      const int r = cy + dv - origin.y;
      const float* above = smooth.ptr<float>(r - 1);
      const float* row = smooth.ptr<float>(r);
      const float* below = smooth.ptr<float>(r + 1);
      const double dy = cy + dv - qy;
      for (int du = -reach; du <= reach; ++du) {
        const double dx = cx + du - qx;
        const double r2 = (dx * dx + dy * dy) / radius2;
        if (r2 >= 1) continue;
        const double w = (1 - r2) * (1 - r2);
        const int k = cx + du - origin.x;
        const double gx = 0.5 * (row[k + 1] - row[k - 1]), gy = 0.5 * (below[k] - above[k]);
        const double wxx = w * gx * gx, wxy = w * gx * gy, wyy = w * gy * gy;
        a += wxx, b += wxy, c += wyy;
        rx += wxx * dx + wxy * dy;
        ry += wxy * dx + wyy * dy;
      }
    }
    const double det = a * c - b * b;
    // Both directions of gradient needed: a lone edge (or a flat window) places no corner. The
    // ratio is 0.25 at a right-angled junction, above 0.03 at a 20-degree one.
    if (!(det > kMinDeterminantOverTrace2 * (a + c) * (a + c))) return false;
    const double step_x = (c * rx - b * ry) / det, step_y = (a * ry - b * rx) / det;
    qx += step_x, qy += step_y;
    // Run out of its window: the junction was not where the corner started (on Bouguet's images a
    // weak window ran 80 px).
    if (!(std::hypot(qx - corner->x, qy - corner->y) <= radius)) return false;  // NaN fails too
    if (step_x * step_x + step_y * step_y < options.epsilon_px * options.epsilon_px) break;
  }
  *corner = cv::Point2f(static_cast<float>(qx), static_cast<float>(qy));
  return true;
}

}  // namespace

void refineCornersSubpixel(const cv::Mat& grey, int half_window, std::vector<cv::Point2f>& uv,
                           const SubpixelCornerOptions& options) {
  CV_Assert(grey.type() == CV_8UC1 && half_window >= 1);
  const auto opencv = [&](std::vector<cv::Point2f>& corners) {
    if (corners.empty()) return;
    cv::cornerSubPix(grey, corners, cv::Size(half_window, half_window), cv::Size(-1, -1),
                     cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, options.max_iterations,
                                      options.epsilon_px));
  };
  if (options.method == "opencv") return opencv(uv);
  std::vector<cv::Point2f> unplaced;
  std::vector<size_t> where;
  for (size_t k = 0; k < uv.size(); ++k)
    if (!refineCorner(grey, half_window, options, &uv[k])) {
      unplaced.push_back(uv[k]);
      where.push_back(k);
    }
  opencv(unplaced);
  for (size_t k = 0; k < where.size(); ++k) uv[where[k]] = unplaced[k];
}

}  // namespace slamcmp
