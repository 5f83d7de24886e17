#pragma once
// A plan's runs on this machine: each its own `slamcmp run` process (the command jobs.txt lists),
// `jobs` at once, its output into its log. Ctrl-C, SIGTERM or SIGHUP stop the compare: no run
// starts, the running ones get SIGTERM (they stop at their next frame and leave whole outputs
// marked interrupted), and all are waited for.
#include <string>

#include "eval/report/experiment_plan.h"

namespace slamcmp {

// Returns false when interrupted.
bool runPlannedJobs(const Plan& plan, const std::string& dir, int jobs);

// The line a run's log ends with when compare stopped it before it could leave outputs of its own
// (a signal in its first fraction of a second, before its handler): collect calls it interrupted.
inline constexpr const char* kStoppedByCompare = "slamcmp compare: stopped";
// The line a run's log ends with when it died on a signal of its own (a crash), written by
// compare's runner and by each jobs.txt line (GNU parallel, Slurm), followed by the signal's number.
inline constexpr const char* kEndedOnSignal = "slamcmp: the run ended on signal ";

}  // namespace slamcmp
