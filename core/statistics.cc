#include "core/statistics.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace slamcmp {

double median(std::vector<double> values) {
  if (values.empty()) return std::numeric_limits<double>::quiet_NaN();
  const auto mid = values.begin() + static_cast<long>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  if (values.size() % 2) return *mid;
  return 0.5 * (*std::max_element(values.begin(), mid) + *mid);  // the lower middle is the largest below
}

Statistics computeStatistics(std::vector<double> values) {
  Statistics s;
  s.count = static_cast<int>(values.size());
  if (values.empty()) {
    s.mean = s.median = s.std = s.rmse = s.min = s.max = s.p99 = std::numeric_limits<double>::quiet_NaN();
    return s;
  }
  const double n = static_cast<double>(values.size());
  double sum = 0.0, squares = 0.0;
  for (double v : values) {
    sum += v;
    squares += v * v;
  }
  s.mean = sum / n;
  double squared_deviation = 0.0;
  for (double v : values) squared_deviation += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(squared_deviation / n);
  s.rmse = std::sqrt(squares / n);
  s.median = median(values);
  std::sort(values.begin(), values.end());
  s.min = values.front();
  s.max = values.back();
  s.p99 = values[std::min(values.size(), static_cast<size_t>(std::ceil(0.99 * n))) - 1];
  return s;
}

}  // namespace slamcmp
