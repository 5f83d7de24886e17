#pragma once
// `compare` and `reproduce`: several back-ends (and cslam modes) on several sequences, in
// parallel, then a markdown report, CSV tables and figures (SPEC section 7).
#include <string>
#include <vector>

namespace slamcmp {

// A back-end with an optional mode, written "cslam", "cslam:calibration", "monoslam".
struct Method {
  std::string backend;
  std::string mode;
  std::string label() const { return mode.empty() ? backend : backend + ":" + mode; }
  std::string slug() const { return mode.empty() ? backend : backend + "-" + mode; }
};
// Comma-separated list; throws InputError for an unknown back-end or an empty list.
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
