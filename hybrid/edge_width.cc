#include "hybrid/edge_width.h"

#include <cmath>
#include <vector>

#include "core/image.h"

namespace slamcmp {

std::optional<double> edgeSpread(const cv::Mat& grey, const Vec2& at, const Vec2& normal, double half_length,
                                 double min_step) {
  CV_Assert(grey.type() == CV_8UC1);
  constexpr double kStep = 0.5;  // pixels between samples along the normal
  const Vec2 n = normal.normalized();
  const int half = static_cast<int>(half_length / kStep);
  if (half < 2) return std::nullopt;
  std::vector<double> level(2 * half + 2);
  for (int k = 0; k < static_cast<int>(level.size()); ++k) {
    const Vec2 p = at + ((k - half - 0.5) * kStep) * n;
    if (!sampleBilinear(grey, p.x(), p.y(), &level[k])) return std::nullopt;
  }
  // The derivative between samples, at t = (k - half) kStep; the step's sign from its sum, and
  // the part of the other sign (noise, a neighbouring edge's tail) left out.
  std::vector<double> d(2 * half + 1);
  double sum = 0;
  for (int k = 0; k < static_cast<int>(d.size()); ++k) sum += d[k] = level[k + 1] - level[k];
  if (!(std::abs(sum) >= min_step)) return std::nullopt;
  double w_sum = 0, t_sum = 0, tt_sum = 0;
  for (int k = 0; k < static_cast<int>(d.size()); ++k) {
    const double w = std::max(0.0, sum > 0 ? d[k] : -d[k]);
    const double t = (k - half) * kStep;
    w_sum += w;
    t_sum += w * t;
    tt_sum += w * t * t;
  }
  if (!(w_sum > 0)) return std::nullopt;
  const double mean = t_sum / w_sum;
  return tt_sum / w_sum - mean * mean;
}

}  // namespace slamcmp
