#include "hybrid/corner_noise.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace slamcmp {

void CornerNoiseOptions::check() const {
  if (!(min_pixel_sigma > 0)) throw OptionError("min_pixel_sigma", "must be positive");
  if (!(time_constant_frames >= 1)) throw OptionError("time_constant_frames", "must be >= 1");
  if (min_dof < 1) throw OptionError("min_dof", "must be >= 1");
}

void CornerNoise::add(const std::vector<double>& plane_errors_px) {
  constexpr int kHomographyDof = 8;
  const int m = static_cast<int>(plane_errors_px.size());
  if (!options_.enabled || 2 * m <= kHomographyDof) return;
  const double decay = std::exp(-1.0 / options_.time_constant_frames);
  double sum = 0;
  for (const double e : plane_errors_px) sum += e * e;
  sum_squares_ = decay * sum_squares_ + sum;
  dof_ = decay * dof_ + (2 * m - kHomographyDof);
}

double CornerNoise::pixelSigma() const {
  if (!options_.enabled || dof_ < options_.min_dof) return set_pixel_sigma_;
  return std::max(options_.min_pixel_sigma, std::sqrt(sum_squares_ / dof_));
}

}  // namespace slamcmp
