#include "eval/metrics/associate.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "core/error.h"

namespace slamcmp {

namespace {

std::vector<double> timestamps(const Trajectory& trajectory, const char* name) {
  std::vector<double> t(trajectory.size());
  for (size_t i = 0; i < t.size(); ++i) {
    t[i] = trajectory[i].timestamp;
    if (i > 0 && !(t[i] >= t[i - 1]))
      throw InputError(name, "timestamp goes back in time (pose " + std::to_string(i) + ")");
  }
  return t;
}

// evo: index = argmin |times - t| (the first of equal minima). The times do not decrease, so the
// differences fall then rise: the minimum is next to the insertion point, and repeated times or
// rounding can only make equal neighbours, which the walk to the left resolves as argmin does.
size_t nearestIndex(const std::vector<double>& times, double t) {
  const size_t k =
      static_cast<size_t>(std::lower_bound(times.begin(), times.end(), t) - times.begin());
  size_t best = k < times.size() ? k : times.size() - 1;
  if (k > 0 && std::abs(times[k - 1] - t) <= std::abs(times[best] - t)) best = k - 1;
  while (best > 0 && std::abs(times[best - 1] - t) == std::abs(times[best] - t)) --best;
  return best;
}

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

}  // namespace

PosePairs associateByTime(const Trajectory& groundtruth, const Trajectory& estimate,
                          double max_diff) {
  const std::vector<double> t_gt = timestamps(groundtruth, "ground truth");
  const std::vector<double> t_est = timestamps(estimate, "estimate");
  PosePairs pairs;
  if (t_gt.empty() || t_est.empty())
    throw InputError("", "nothing to associate: a trajectory holds no pose");

  // evo searches the shorter trajectory's stamps in the longer one's; on equal length the
  // second (estimate) is the shorter.
  const bool estimate_longer = t_est.size() > t_gt.size();
  const std::vector<double>& t_short = estimate_longer ? t_gt : t_est;
  const std::vector<double>& t_long = estimate_longer ? t_est : t_gt;
  std::vector<size_t>& index_short = estimate_longer ? pairs.groundtruth : pairs.estimate;
  std::vector<size_t>& index_long = estimate_longer ? pairs.estimate : pairs.groundtruth;
  for (size_t i = 0; i < t_short.size(); ++i) {
    const size_t j = nearestIndex(t_long, t_short[i]);
    if (std::abs(t_long[j] - t_short[i]) <= max_diff) {
      index_short.push_back(i);
      index_long.push_back(j);
    }
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
