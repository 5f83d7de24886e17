#include <iostream>
#include <limits>

#include "core/error.h"
#include "eval/app/backends.h"
#include "eval/app/commands.h"
#include "eval/app/compare.h"
#include "eval/app/compare_plan.h"
#include "eval/app/run_sequence.h"

namespace slamcmp {

void addCompareCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "compare",
      "run several back-ends on several sequences (trials, sweeps) and write a report with tables and figures; "
      "or plan the runs for GNU parallel or Slurm (--plan) and collect them (--collect)");
  auto sequences = std::make_shared<std::vector<std::string>>();
  auto backends = std::make_shared<std::string>(backendNames(","));
  auto options = std::make_shared<CompareOptions>();
  auto plan_dir = std::make_shared<std::string>();
  auto collect_dir = std::make_shared<std::string>();
  cmd->add_option("--sequence", *sequences, "a sequence folder (repeat for more)")->check(nonEmptyPath());
  std::string every;
  for (const Method& m : allMethods()) every += (every.empty() ? "" : ",") + m.backend + ":" + (m.mode.empty() ? findBackend(m.backend).modes.front().name : m.mode);
  cmd->add_option("--backends", *backends,
                  "comma-separated back-ends, each optionally with a mode (default: each back-end's default "
                  "mode) and, for those that take --init, a start: backend[:mode][@board|groundtruth|none] (e.g. "
                  "monoslam,monoslam@none); all of them: " + every)
      ->capture_default_str();
  auto* out = cmd->add_option("--out", options->out_dir, "output folder: report.md, results.csv, *.csv, figures/, runs/, "
                                                        "logs/, and the plan (plan.json, jobs.txt, slurm.sbatch)")
                  ->check(nonEmptyPath());
  cmd->add_option("--jobs", options->jobs, "runs at once")->capture_default_str()->check(CLI::Range(1, 64));
  cmd->add_option("--max-frames", options->max_frames, "stop each run after N frames (and render trials that long)")
      ->check(CLI::Range(0, std::numeric_limits<int>::max()));
  cmd->add_option("--trials", options->trials,
                  "runs of each back-end on each sequence: trial k re-renders a synthetic sequence (one with "
                  "info.yaml) with seed k, or runs a real one with `run --seed k`")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  cmd->add_option("--set", options->sets,
                  "sweep one option: SECTION.KEY=V1,V2,... (the YAML's path, e.g. cslam.features.max_features=100,150,200); "
                  "several make a grid of one back-end's values (repeatable)");
  cmd->add_option("--config", options->configs,
                  "an option file as `run --config` reads it (one section per back-end): each back-end with a "
                  "section in it runs with it, labelled config=NAME; `defaults` runs them with their defaults too "
                  "(repeatable; a back-end no file has a section for runs with its defaults; --set sweeps apply to each)")
      ->check(nonEmptyPath());
  auto* plan = cmd->add_option("--plan", *plan_dir,
                               "write DIR/plan.json, DIR/jobs.txt (one `slamcmp run` a line: `parallel < jobs.txt`) "
                               "and DIR/slurm.sbatch (`sbatch DIR/slurm.sbatch`) instead of running")
                   ->check(nonEmptyPath());
  auto* array_tasks = cmd->add_option("--array-tasks", options->array_tasks,
                                      "with --plan: the Slurm array's tasks at most (a cluster's MaxArraySize - 1); "
                                      "task k runs lines k, k + N, ... of jobs.txt")
                          ->check(CLI::Range(1, 1000000))
                          ->capture_default_str();
  array_tasks->needs(plan);
  auto* collect = cmd->add_option("--collect", *collect_dir,
                                  "the report of a plan's finished runs, into DIR, exactly as compare writes it "
                                  "(every other option comes from DIR/plan.json)")
                      ->check(nonEmptyPath());
  plan->excludes(out);
  collect->excludes(out);
  collect->excludes(plan);
  cmd->callback([cmd, sequences, backends, options, plan_dir, collect_dir] {
    installInterruptHandler();
    if (!collect_dir->empty()) {
      // The plan decided them: one given here would be ignored.
      for (const char* option : {"--sequence", "--backends", "--trials", "--set", "--config", "--max-frames", "--jobs"})
        if (cmd->count(option) > 0)
          throw InputError("--collect", std::string("takes no ") + option + " (DIR/plan.json has the experiment's)");
      std::vector<UnfinishedRun> unfinished;
      const std::string report = collectCompare(*collect_dir, &unfinished);
      sayCompareReport(*collect_dir, report, unfinished);
      return;
    }
    if (sequences->empty()) throw InputError("--sequence", "give at least one sequence");
    options->sequences = *sequences;
    options->methods = parseMethods(*backends);
    if (!plan_dir->empty()) {
      options->out_dir = *plan_dir;
      const size_t runs = planCompare(*options);
      std::cout << "plan: " << runs << " runs in " << *plan_dir << "/jobs.txt; run them with `parallel < "
                << shellQuoted(*plan_dir + "/jobs.txt") << "` or `sbatch " << shellQuoted(*plan_dir + "/slurm.sbatch")
                << "`, then `slamcmp compare --collect " << shellQuoted(*plan_dir) << "`\n";
      return;
    }
    if (options->out_dir.empty()) throw InputError("compare", "give --out DIR (or --plan DIR, or --collect DIR)");
    std::vector<UnfinishedRun> unfinished;
    const std::string report = runCompare(*options, &unfinished);
    sayCompareReport(options->out_dir, report, unfinished);
  });
}

}  // namespace slamcmp
