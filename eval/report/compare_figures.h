#pragma once
// compare's figures for one sequence: the thesis's figures 3.7 to 3.14 (trajectory, position and
// rotation against frame) with the ground truth added, error and time per frame, and the map
// against the true scene.
#include <string>
#include <vector>

#include "eval/report/compare_report.h"

namespace slamcmp {

// Writes <fig_dir>/<sequence>_<figure>.png; returns the paths written.
std::vector<std::string> writeCompareFigures(const SequenceInfo& seq, const std::vector<RunResult>& runs,
                                             const std::string& fig_dir);

}  // namespace slamcmp
