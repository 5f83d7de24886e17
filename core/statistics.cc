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

double chiSquaredQuantile(double dof, double probability) {
  // Standard normal quantile by Acklam's rational approximation (central region and tails).
  const double p = probability;
  const double a[] = {-3.969683028665376e+01, 2.209460984245205e+02, -2.759285104469687e+02,
                      1.383577518672690e+02, -3.066479806614716e+01, 2.506628277459239e+00};
  const double b[] = {-5.447609879822406e+01, 1.615858368580409e+02, -1.556989798598866e+02,
                      6.680131188771972e+01, -1.328068155288572e+01};
  const double c[] = {-7.784894002430293e-03, -3.223964580411365e-01, -2.400758277161838e+00,
                      -2.549732539343734e+00, 4.374664141464968e+00, 2.938163982698783e+00};
  const double d[] = {7.784695709041462e-03, 3.224671290700398e-01, 2.445134137142996e+00,
                      3.754408661907416e+00};
  double z;
  if (p < 0.02425) {
    const double q = std::sqrt(-2 * std::log(p));
    z = (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else if (p > 1 - 0.02425) {
    const double q = std::sqrt(-2 * std::log(1 - p));
    z = -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
        ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1);
  } else {
    const double q = p - 0.5, r = q * q;
    z = (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
        (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1);
  }
  const double k = dof, h = 2.0 / (9.0 * k);
  return k * std::pow(1 - h + z * std::sqrt(h), 3);
}

double ransacTrials(double inlier_ratio, int sample_size, double confidence) {
  const double p_good = std::pow(inlier_ratio, sample_size);
  if (p_good >= 1.0) return 0;
  if (!(p_good > 0)) return HUGE_VAL;
  return std::max(0.0, std::ceil(std::log(1 - confidence) / std::log1p(-p_good)));
}

}  // namespace slamcmp
