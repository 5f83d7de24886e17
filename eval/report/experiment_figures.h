#pragma once
// compare's figures over the whole experiment: box plots of each method's ATE over the trials per
// sequence (rpg_trajectory_evaluation's), accuracy against CPU time of a sweep's settings
// (SLAMBench's design-space view), and each sequence's CPU time per frame split into the
// back-ends' stages, stacked (ov_eval's timing bars), and each filter's NEES averaged over the
// trials frame by frame against its 95 % interval (ov_eval's NEES plot).
#include <string>
#include <vector>

#include "eval/report/compare_report.h"
#include "eval/report/experiment_plan.h"

namespace slamcmp {

// A sweep's setting ("features.quality_level=0.05 features.max_features=100") as its point's label
// in the figure: each option's last key with its value ("quality_level=0.05 max_features=100").
std::string sweepPointLabel(const std::string& setting);

// Writes <fig_dir>/ate_boxplot.png (several trials), sweep_ate_cpu.png (a sweep),
// <sequence>_stages.png (runs with stages) and <sequence>_anees.png (several trials of a filter
// that scored its covariances); returns the paths written.
std::vector<std::string> writeExperimentFigures(const Plan& plan, const std::vector<SequenceInfo>& seqs,
                                                const std::vector<RunResult>& runs, const std::string& fig_dir);

}  // namespace slamcmp
