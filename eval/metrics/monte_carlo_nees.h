#pragma once
// A filter's consistency over Monte Carlo trials (Bar-Shalom, Li and Kirubarajan 2001, 5.4.2):
// at each time step the NEES averaged over the M trials that scored it (ANEES), against the 95 %
// interval of chi-square with M x dof degrees of freedom over M. A consistent filter's ANEES is
// inside on about 95 % of the steps. This is the test a single run cannot give: its NEES is
// correlated from frame to frame (errors of a consistent filter are), so the chi-square bounds of
// a run's time average (summary.json's nees) are far too narrow for it; across independent trials
// the samples at one step are independent. OpenVINS's ov_eval plots the same.
#include <optional>
#include <vector>

#include "eval/metrics/nees.h"

namespace slamcmp {

struct MonteCarloNees {
  // The steps scored by 2 trials or more, in time order.
  std::vector<double> timestamps, anees, lower, upper;
  std::vector<int> trials;
  int inside = 0, above = 0, below = 0;  // steps with the ANEES inside, above and below their interval
  double mean = 0;                       // of the ANEES over the steps
  int steps() const { return static_cast<int>(anees.size()); }
};

// runs[i]: trial i's per-frame NEES (nees.csv), from independent noise (a synthetic sequence
// rendered again with another seed: the same images rerun with another seed of the back-end are
// not independent trials). Steps are matched by timestamp to a microsecond (the trials of a
// synthetic sequence share their timestamps; timestamps beyond 1e12 s are left out). Nothing when
// no step has 2 trials.
std::optional<MonteCarloNees> monteCarloNees(const std::vector<std::vector<TimedNees>>& runs, int dof = 6);

}  // namespace slamcmp
