#pragma once
// A compare as a list of runs (the unit of work: one `slamcmp run` each), written to plan.json by
// `compare --plan` and read back by `compare --collect`, so that the report depends on nothing but
// the plan and the runs' output folders, wherever they ran.
#include <optional>
#include <string>
#include <vector>

#include "eval/report/compare_report.h"

namespace slamcmp {

struct PlannedRun {
  size_t sequence = 0;        // index into Plan::sequences (a row of the tables)
  size_t method = 0;          // index into Plan::methods (a column: back-end, mode and setting)
  int trial = 1;              // 1..trials
  std::string seed_kind;      // "render" (the trial's sequence rendered with `seed`), "backend"
                              // (run --seed), "" (the sequence and the back-end's seeds as given)
  std::optional<int> seed;
  std::string sequence_path;  // the trial's sequence (absolute)
  std::string dir;            // the run's output folder, relative to the plan's folder
  std::string log;            // its stdout and stderr, relative to the plan's folder
  std::vector<std::string> sets;   // --set KEY=VALUE of its setting
  std::string config;              // its --config file (absolute), "" for the back-end's defaults
  std::vector<std::string> argv;   // the whole `slamcmp run` command (absolute paths)
};

struct Plan {
  std::vector<std::string> sequences;       // the given sequences (absolute)
  std::vector<std::string> sequence_names;  // their names, as the tables show them
  std::vector<Method> methods;              // every back-end, mode and setting, in table order
  std::vector<std::string> swept_keys;      // the --set keys, in order ("cslam.features.max_features")
  std::vector<std::string> configs;         // the --config files (absolute), in order
  int trials = 1;
  int max_frames = -1;                      // per run; < 0: all
  std::vector<PlannedRun> runs;             // sequence-major, then method, then trial
  // The folder the plan was written into (absolute): trial renders inside it are found again in
  // a folder moved or copied back from a cluster's scratch (a plan written before this field: "").
  std::string dir;
};

nlohmann::json planToJson(const Plan& plan);
// Throws InputError naming `where` (the plan.json path) and the field for a malformed plan.
Plan planFromJson(const nlohmann::json& j, const std::string& where);

// The run's `--set` value of a swept key, "" when the run's back-end does not take it.
std::string sweptValue(const PlannedRun& run, const std::string& key);

}  // namespace slamcmp
