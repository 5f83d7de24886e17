#pragma once
// `compare` and `reproduce`: several back-ends (and their modes) on several sequences, in
// parallel, then the report (eval/report/compare_report.h).
#include <string>
#include <vector>

#include "eval/report/compare_report.h"

namespace slamcmp {

// "backend" or "backend:mode" as a Method with the registry's colour; InputError(where, ...) for
// an unknown back-end or mode.
Method methodOf(const std::string& backend, const std::string& mode, const std::string& where);
// Every registered back-end in every mode, in registry order (reproduce's list).
std::vector<Method> allMethods();
// Comma-separated list; throws InputError for an unknown back-end or mode, an entry listed twice or
// an empty list.
std::vector<Method> parseMethods(const std::string& list);

struct CompareOptions {
  std::vector<std::string> sequences;
  std::vector<Method> methods;
  std::string out_dir;
  int jobs = 2;         // runs at once
  int max_frames = -1;  // per run; < 0: all
};

// Runs everything, writes <out>/report.md, <out>/*.csv, <out>/figures/*.png and <out>/runs/.
// Returns the report's path. A run that fails is reported in the tables, not fatal; a sequence
// that cannot be opened is an InputError before anything runs.
std::string runCompare(const CompareOptions& options);

}  // namespace slamcmp
