#pragma once
// results.csv: one row a run (sequence, method, trial, seed kind and seed, the option file, the
// swept values, status, first lost frame, alignment, every number below, the run's folder and its
// error). The report's tables average these same numbers over trials, and the numbers are
// written so that they read back exactly (shortest round-trip), so that any statistic in the
// report can be recomputed from results.csv.
#include <string>
#include <vector>

#include "eval/report/compare_report.h"
#include "eval/report/experiment_plan.h"

namespace slamcmp {

struct RunColumn {
  const char* name;                     // results.csv's header
  double (*value)(const RunResult& r);  // NaN when the run has no such number
};

// frames, tracked, posed_percent, scale, ate_trans_rmse_m, ate_rot_rmse_deg, ate_rot_undetermined,
// rpe_trans_rmse_m, rpe_rot_rmse_deg, drift_trans_percent, drift_rot_deg_per_m, ms_median,
// cpu_ms_median, cpu_ms_mean, map_points, map_median_m, map_within_1cm, nees_mean,
// nees_position_mean, nees_orientation_mean, and from summary.json's board_view:
// gap_worst_over_allowance (the worst gap's), gap_lost (over every gap),
// after_return_over_settled, partial_over_whole.
const std::vector<RunColumn>& runColumns();

// The column's number of a run that finished (status ok), else NaN.
double runValue(const RunResult& r, const std::string& column);

// The shortest text that reads back as exactly `v`; "" for NaN.
std::string exactNumber(double v);
// A CSV cell: quoted (quotes doubled) when it holds a comma, a quote or a line break.
std::string csvText(const std::string& s);

void writeResultsCsv(const Plan& plan, const std::vector<RunResult>& runs, const std::string& path);

}  // namespace slamcmp
