#pragma once
// The one summary of a sample that every file and table reports (run timings, trajectory and map
// errors), with numpy's conventions so that the trajectory figures agree with evo's.
#include <vector>

namespace slamcmp {

struct Statistics {
  int count = 0;
  // In the sample's unit. median: the middle value, or the mean of the two middle values for an
  // even count (numpy.median); std: population (ddof 0); rmse: the root of the mean square;
  // p99: the nearest-rank 99th percentile (the smallest value with 99 % of the sample at or below).
  double mean = 0, median = 0, std = 0, rmse = 0, min = 0, max = 0, p99 = 0;
};

// An empty sample has count 0 and NaN statistics: no number stands for what was not measured.
Statistics computeStatistics(std::vector<double> values);

// The median as Statistics defines it; NaN for an empty sample.
double median(std::vector<double> values);

// The chi-squared distribution's quantile for `dof` degrees of freedom at `probability`: Wilson
// and Hilferty's cube of a normal quantile (Acklam's, relative error under 1.2e-9). Within 1 % of
// the exact value for dof >= 2 and probabilities 0.9 to 0.999, within 0.1 % from 30 dof up: the
// filters' gates and the NEES bounds.
double chiSquaredQuantile(double dof, double probability);

// Samples to draw for an all-inlier one with probability `confidence`, at this inlier ratio and
// sample size: log(1 - confidence) / log(1 - ratio^size), rounded up (Fischler and Bolles 1981;
// COLMAP's ComputeNumTrials); +inf when the ratio is 0. log1p: for ratio^size under 1e-16, 1 - it
// is 1 in doubles, and the quotient was -inf.
double ransacTrials(double inlier_ratio, int sample_size, double confidence);

}  // namespace slamcmp
