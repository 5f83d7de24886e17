#include "ekf/patch_search.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>
#include <opencv2/imgproc.hpp>

namespace slamcmp {

namespace {

// Offset of a parabola's vertex through (-1, a), (0, b), (1, c), in [-0.5, 0.5].
double parabolaPeak(double a, double b, double c) {
  const double den = a - 2 * b + c;
  if (!(den < 0)) return 0.0;
  return std::clamp(0.5 * (a - c) / den, -0.5, 0.5);
}

}  // namespace

cv::Rect ellipsesBoundingBox(const std::vector<SearchEllipse>& ellipses, double gate) {
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const auto& e : ellipses) {
    const double hx = gate * std::sqrt(std::max(0.0, e.S(0, 0)));
    const double hy = gate * std::sqrt(std::max(0.0, e.S(1, 1)));
    x0 = std::min(x0, e.centre.x() - hx);
    x1 = std::max(x1, e.centre.x() + hx);
    y0 = std::min(y0, e.centre.y() - hy);
    y1 = std::max(y1, e.centre.y() + hy);
  }
  if (ellipses.empty() || !std::isfinite(x0 + x1 + y0 + y1)) return cv::Rect();
  const int ix0 = static_cast<int>(std::ceil(x0)), iy0 = static_cast<int>(std::ceil(y0));
  const int ix1 = static_cast<int>(std::floor(x1)), iy1 = static_cast<int>(std::floor(y1));
  if (ix1 < ix0 || iy1 < iy0) return cv::Rect();
  return cv::Rect(ix0, iy0, ix1 - ix0 + 1, iy1 - iy0 + 1);
}

std::vector<PatchMatch> searchEllipses(const cv::Mat& grey, const cv::Mat& templ,
                                       const std::vector<SearchEllipse>& ellipses, double gate,
                                       double min_ncc) {
  CV_Assert(templ.type() == CV_32F && templ.rows == templ.cols && templ.rows % 2 == 1);
  std::vector<PatchMatch> matches;
  const int half = templ.rows / 2;
  // Centres whose template lies inside the image.
  const cv::Rect valid(half, half, grey.cols - 2 * half, grey.rows - 2 * half);
  const cv::Rect box = ellipsesBoundingBox(ellipses, gate) & valid;
  if (box.empty()) return matches;

  cv::Mat region;
  grey(cv::Rect(box.x - half, box.y - half, box.width + 2 * half, box.height + 2 * half))
      .convertTo(region, CV_32F);
  cv::Mat score;  // score(i, j) is the correlation centred at pixel (box.x + j, box.y + i)
  cv::matchTemplate(region, templ, score, cv::TM_CCOEFF_NORMED);

  std::vector<Mat2> S_inv;
  for (const auto& e : ellipses) S_inv.push_back(e.S.inverse());
  const double gate2 = gate * gate;
  auto inside = [&](int u, int v) {
    for (size_t k = 0; k < ellipses.size(); ++k) {
      const Vec2 d = Vec2(u, v) - ellipses[k].centre;
      if (d.dot(S_inv[k] * d) <= gate2) return true;
    }
    return false;
  };
  auto at = [&](int i, int j) { return static_cast<double>(score.at<float>(i, j)); };
  // A local maximum over its 8 neighbours (ties broken towards the first in scan order).
  auto isPeak = [&](int i, int j) {
    const float s = score.at<float>(i, j);
    for (int di = -1; di <= 1; ++di)
      for (int dj = -1; dj <= 1; ++dj) {
        if ((di == 0 && dj == 0) || i + di < 0 || j + dj < 0 || i + di >= score.rows || j + dj >= score.cols)
          continue;
        const float t = score.at<float>(i + di, j + dj);
        if (t > s || (t == s && (di < 0 || (di == 0 && dj < 0)))) return false;
      }
    return true;
  };

  const float threshold = static_cast<float>(min_ncc);
  for (int i = 0; i < score.rows; ++i) {
    const float* row = score.ptr<float>(i);
    for (int j = 0; j < score.cols; ++j) {
      if (!(row[j] >= threshold) || !isPeak(i, j) || !inside(box.x + j, box.y + i)) continue;
      const double b = row[j];
      const double du = (j > 0 && j + 1 < score.cols) ? parabolaPeak(at(i, j - 1), b, at(i, j + 1)) : 0.0;
      const double dv = (i > 0 && i + 1 < score.rows) ? parabolaPeak(at(i - 1, j), b, at(i + 1, j)) : 0.0;
      PatchMatch m;
      m.ncc = b;
      m.uv = Vec2(box.x + j + du, box.y + i + dv);
      matches.push_back(m);
    }
  }
  std::sort(matches.begin(), matches.end(), [](const PatchMatch& a, const PatchMatch& b) { return a.ncc > b.ncc; });
  return matches;
}

}  // namespace slamcmp
