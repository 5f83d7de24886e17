#include "geometry/hartley_normalisation.h"

#include <cmath>

namespace slamcmp {

Mat3 hartleyNormalisation(const std::vector<Vec2>& points) {
  Vec2 mean = Vec2::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(points.size());
  double dist = 0;
  for (const auto& p : points) dist += (p - mean).norm();
  dist /= static_cast<double>(points.size());
  const double s = dist > 0 ? std::sqrt(2.0) / dist : 1.0;
  Mat3 T;
  T << s, 0, -s * mean.x(), 0, s, -s * mean.y(), 0, 0, 1;
  return T;
}

}  // namespace slamcmp
