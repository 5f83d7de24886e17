#pragma once
// `compare` and `reproduce`: several back-ends (and their modes, and settings of their options) on
// several sequences, several trials each. A compare is a plan of runs (compare_plan.h), the runs
// (each one `slamcmp run` process: job_runner.h, GNU parallel or Slurm) and the report collected
// from their folders (collectCompare below, the report itself eval/report/compare_report.h); locally
// the three follow each other.
#include <string>
#include <vector>

#include "eval/report/compare_report.h"

namespace slamcmp {

// A back-end and its mode ("" = its default) as a Method with the registry's colour;
// InputError(where, ...) for an unknown back-end or mode.
Method methodOf(const std::string& backend, const std::string& mode, const std::string& where);
// Every registered back-end in every mode, in registry order (reproduce's list).
std::vector<Method> allMethods();
// Comma-separated list of backend[:mode][@init]; throws InputError for an unknown back-end, mode or
// start, an entry listed twice or an empty list.
std::vector<Method> parseMethods(const std::string& list);

struct CompareOptions {
  std::vector<std::string> sequences;
  std::vector<Method> methods;
  std::string out_dir;
  int jobs = 2;         // runs at once
  int max_frames = -1;  // per run; < 0: all
  int trials = 1;       // > 1: trial k re-renders a synthetic sequence with seed k, or runs a real one with --seed k
  std::vector<std::string> sets;  // "SECTION.KEY=V1,V2,...": a sweep; several make a grid per back-end
  // Option files (`run --config`'s): a back-end runs with each that has its section, and with its
  // defaults when "defaults" is among them or none has its section; the sweeps apply to each.
  std::vector<std::string> configs;
  std::string slamcmp;  // the binary the runs execute; "" = this process's own (tests give slamcmp's)
  // --plan's Slurm array: at most this many tasks, task k running lines k, k + n, ... of jobs.txt
  // (Slurm's default MaxArraySize, 1001, takes indices up to 1000).
  int array_tasks = 1000;
};

// A run of a compare that did not finish, as its report lists it.
struct UnfinishedRun {
  std::string dir;     // runs/NAME, relative to the compare's folder
  std::string status;  // failed | interrupted | unfinished (running, or killed without a word) | not run
  std::string error;   // why ("" if nothing says)
};

// Plans, runs every run (options.jobs at once, each a `slamcmp run` process) and collects: writes
// <out>/plan.json, jobs.txt, slurm.sbatch, runs/, logs/, results.csv, report.md, the tables'
// CSVs and figures/. Returns the report's path; `unfinished` (if given) receives the runs not
// finished. A run that fails is reported in the tables, not fatal (sayCompareReport says it); bad
// options or a sequence that cannot be opened are InputErrors before anything runs.
// Throws Interrupted (after writing the report) when interrupted.
std::string runCompare(const CompareOptions& options, std::vector<UnfinishedRun>* unfinished = nullptr);

// The end of compare, --collect and reproduce: the report's path on stdout (with how many runs did
// not finish); then each failed run on stderr, one line each naming its folder and why, and an
// InputError (exit 2): a compare whose runs failed is not a finished one. Runs not run yet (a plan
// collected early) or interrupted are only counted: the report lists them. `dir`: the compare's folder.
void sayCompareReport(const std::string& dir, const std::string& report, const std::vector<UnfinishedRun>& unfinished);

// compare --plan: writes <out>/plan.json, jobs.txt (one `slamcmp run` a line) and slurm.sbatch
// (an array job over jobs.txt), rendering the trials' synthetic sequences; runs nothing. Returns
// the number of runs.
size_t planCompare(const CompareOptions& options);

// compare --collect DIR: the report from a plan's finished runs, exactly as runCompare writes it.
// Returns the report's path; `unfinished` (if given) receives the runs not finished.
std::string collectCompare(const std::string& dir, std::vector<UnfinishedRun>* unfinished = nullptr);

}  // namespace slamcmp
