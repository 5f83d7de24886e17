#pragma once
// compare's plan: which runs a compare makes (every sequence x back-end, mode and setting x trial),
// each as one self-contained `slamcmp run` command, and the files that hand them to a scheduler:
// plan.json (read back by --collect), jobs.txt (a command a line: `parallel < jobs.txt`) and
// slurm.sbatch (a Slurm array job over jobs.txt).
#include <string>

#include "eval/app/compare.h"
#include "eval/report/experiment_plan.h"

namespace slamcmp {

// Checks the options (InputError naming the option), opens every sequence, renders the trials'
// synthetic sequences into <out>/sequences/seed<k>/, and lists the runs. Removes the planned runs'
// old folders and logs, so that a collect never reads a previous plan's run.
Plan makePlan(const CompareOptions& options);

// plan.json, jobs.txt and slurm.sbatch in `dir` (the plan's absolute folder); the Slurm array has
// min(runs, array_tasks) tasks, task k running lines k, k + n, ... (n that count), so a task's id
// names the same runs however the array is submitted (`sbatch --array=3` reruns task 3).
void writePlanFiles(const Plan& plan, const std::string& dir, int array_tasks = 1000);

// `s` as one word for sh: as it is when it holds only safe characters, else in single quotes.
std::string shellQuoted(const std::string& s);

// One line of jobs.txt: the run's environment, its command and its output into its log.
std::string jobLine(const PlannedRun& run, const std::string& dir);

}  // namespace slamcmp
