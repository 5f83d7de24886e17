#include "eval/metrics/associate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.h"

namespace slamcmp {

std::vector<double> timestampsInOrder(const Trajectory& trajectory, const char* name) {
  std::vector<double> t(trajectory.size());
  for (size_t i = 0; i < t.size(); ++i) {
    t[i] = trajectory[i].timestamp;
    if (i > 0 && !(t[i] >= t[i - 1]))
      throw InputError(name, "timestamp goes back in time (pose " + std::to_string(i) + ")");
  }
  return t;
}

// The times do not decrease, so the differences fall then rise: the minimum is next to the
// insertion point, and repeated times or rounding can only make equal neighbours, which the walk
// to the left resolves as evo's argmin does.
size_t nearestTimeIndex(const std::vector<double>& times, double t) {
  const size_t k =
      static_cast<size_t>(std::lower_bound(times.begin(), times.end(), t) - times.begin());
  size_t best = k < times.size() ? k : times.size() - 1;
  if (k > 0 && std::abs(times[k - 1] - t) <= std::abs(times[best] - t)) best = k - 1;
  while (best > 0 && std::abs(times[best - 1] - t) == std::abs(times[best] - t)) --best;
  return best;
}

namespace {

std::string range(const std::vector<double>& t) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.15g .. %.15g", t.front(), t.back());
  return buf;
}

std::string number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", x);
  return buf;
}

// The factor 10^(3k), k != 0, that the estimate's times are of the ground truth's when both their
// last times and their spans differ by it (within a factor 2.8): one file in s, the other in ms, us
// or ns. 0 when they do not.
double unitFactor(const std::vector<double>& t_gt, const std::vector<double>& t_est) {
  const auto ratioExponent = [](double a, double b) {  // log10(a / b), NaN unless both are positive
    return a > 0 && b > 0 ? std::log10(a / b) : NAN;
  };
  const double end = ratioExponent(std::abs(t_est.back()), std::abs(t_gt.back()));
  const double span = ratioExponent(t_est.back() - t_est.front(), t_gt.back() - t_gt.front());
  for (int k : {-3, -2, -1, 1, 2, 3})
    if (std::abs(end - 3 * k) < 0.45 && (!std::isfinite(span) || std::abs(span - 3 * k) < 0.45))
      return std::pow(10.0, 3 * k);
  return 0;
}

const char* unitPair(double factor) {  // the usual reading of a factor between the two files
  const double k = std::round(std::log10(factor) / 3);
  if (std::abs(k) == 3) return "ns against s";
  if (std::abs(k) == 2) return "us against s (or ns against ms)";
  return "ms against s (or ns against us)";
}

}  // namespace

PosePairs associateByTime(const Trajectory& groundtruth, const Trajectory& estimate,
                          double max_diff, double estimate_offset) {
  const std::vector<double> t_gt = timestampsInOrder(groundtruth, "ground truth");
  std::vector<double> t_est = timestampsInOrder(estimate, "estimate");
  PosePairs pairs;
  if (t_gt.empty() || t_est.empty())
    throw InputError("", "nothing to associate: a trajectory holds no pose");

  // evo searches the shorter trajectory's stamps in the longer one's, shifted by the offset (on
  // equal length the second, the estimate, is the shorter).
  const bool estimate_longer = t_est.size() > t_gt.size();
  const std::vector<double>& t_short = estimate_longer ? t_gt : t_est;
  std::vector<double> t_long = estimate_longer ? t_est : t_gt;
  for (double& t : t_long) t += estimate_longer ? estimate_offset : -estimate_offset;
  std::vector<size_t>& index_short = estimate_longer ? pairs.groundtruth : pairs.estimate;
  std::vector<size_t>& index_long = estimate_longer ? pairs.estimate : pairs.groundtruth;
  for (size_t i = 0; i < t_short.size(); ++i) {
    const size_t j = nearestTimeIndex(t_long, t_short[i]);
    if (std::abs(t_long[j] - t_short[i]) <= max_diff) {
      index_short.push_back(i);
      index_long.push_back(j);
    }
  }
  for (double& t : t_est) t += estimate_offset;  // the messages' times
  // Pairs found by chance across a unit mismatch (s against ms both start near 0) or none at all:
  // say why, with the factor, before an alignment or an RPE complains of too few pairs.
  if (2 * pairs.size() < t_short.size()) {
    if (const double factor = unitFactor(t_gt, t_est); factor != 0) {
      const bool estimate_larger = factor > 1;
      throw InputError("", std::string("time units differ: the ") + (estimate_larger ? "estimate's" : "ground truth's") +
                               " timestamps are " + number(estimate_larger ? factor : 1 / factor) + " times the " +
                               (estimate_larger ? "ground truth's" : "estimate's") + " (" + unitPair(factor) +
                               "?): ground truth times " + range(t_gt) + ", estimate times " + range(t_est) +
                               "; convert one file");
    }
    if (t_est.back() < t_gt.front() || t_gt.back() < t_est.front())
      throw InputError("", "no time overlap: ground truth times " + range(t_gt) + " s, estimate times " +
                               range(t_est) + " s (the estimate " +
                               (t_est.back() < t_gt.front() ? "ends " + number(t_gt.front() - t_est.back()) +
                                                                  " s before the ground truth starts"
                                                            : "starts " + number(t_est.front() - t_gt.back()) +
                                                                  " s after the ground truth ends") +
                               "; do the clocks differ? --max-diff " + number(max_diff) + " s pairs only nearer poses)");
  }
  if (pairs.size() == 0)
    throw InputError("", "no estimate pose is within --max-diff " + number(max_diff) +
                             " s of a ground-truth pose (ground truth times " + range(t_gt) +
                             " s, estimate times " + range(t_est) +
                             " s): are one file's timestamps in ns and the other's in s, or "
                             "do their clocks differ? Otherwise raise --max-diff");
  return pairs;
}

}  // namespace slamcmp
