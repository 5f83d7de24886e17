#include "eval/metrics/monte_carlo_nees.h"

#include <cmath>
#include <map>

#include "core/statistics.h"

namespace slamcmp {

std::optional<MonteCarloNees> monteCarloNees(const std::vector<std::vector<TimedNees>>& runs, int dof) {
  struct Step {
    double sum = 0;
    int trials = 0;
  };
  std::map<long long, Step> steps;  // by the timestamp in microseconds
  for (const std::vector<TimedNees>& run : runs) {
    std::map<long long, double> frames;  // a timestamp a run scored twice counts once (the last)
    for (const TimedNees& r : run)
      if (std::abs(r.timestamp) < 1e12) frames[std::llround(r.timestamp * 1e6)] = r.nees;
    for (const auto& [microseconds, nees] : frames) {
      Step& step = steps[microseconds];
      step.sum += nees;
      ++step.trials;
    }
  }
  MonteCarloNees out;
  double sum = 0;
  for (const auto& [microseconds, step] : steps) {
    if (step.trials < 2) continue;
    const double m = step.trials, anees = step.sum / m;
    const double lower = chiSquaredQuantile(dof * m, 0.025) / m, upper = chiSquaredQuantile(dof * m, 0.975) / m;
    out.timestamps.push_back(static_cast<double>(microseconds) * 1e-6);
    out.anees.push_back(anees);
    out.lower.push_back(lower);
    out.upper.push_back(upper);
    out.trials.push_back(step.trials);
    out.inside += anees >= lower && anees <= upper;
    out.above += anees > upper;
    out.below += anees < lower;
    sum += anees;
  }
  if (out.anees.empty()) return std::nullopt;
  out.mean = sum / out.steps();
  return out;
}

}  // namespace slamcmp
