#pragma once
// compare's report: every run read back from its folder (summary.json, frames.csv,
// trajectory.txt, map.ply), scored, and written as report.md, CSV tables and figures. It reads
// only what a user could read, so runs finished anywhere (compare, GNU parallel, Slurm) give the
// same report.
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/frames_csv.h"
#include "core/trajectory.h"
#include "datasets/scene.h"
#include "eval/metrics/map_metrics.h"
#include "eval/metrics/run_errors.h"

namespace slamcmp {

// A back-end with an optional mode, written "cslam", "cslam:calibration", "monoslam"; its colour and
// thesis column come from the back-end registry.
struct Method {
  std::string backend;
  std::string mode;                // "" = the back-end's default mode
  std::string colour = "#9467bd";  // figure colour
  std::string thesis_method;       // the thesis's Table 3.2 column it stands beside ("" = none)
  std::string label() const { return mode.empty() ? backend : backend + ":" + mode; }
  std::string slug() const { return mode.empty() ? backend : backend + "-" + mode; }
};

struct SequenceInfo {
  std::string path, name;
  int frames = 0;
  std::optional<Trajectory> groundtruth;
  std::optional<SceneGeometry> scene;  // synthetic sequences: the true surfaces (scene.yaml)
};

// One method on one sequence, as read back from its output folder.
struct RunResult {
  Method method;
  std::string dir;
  std::string error;  // non-empty: the run failed
  nlohmann::json summary;
  std::vector<FrameRow> frames;
  Trajectory trajectory;
  std::optional<RunErrors> errors;
  std::vector<MapPoint> map;             // map.ply, read back when the sequence has a scene
  std::optional<MapEvaluation> map_errors;
};

// A number for a table: fixed with `precision` decimals, "-" when not finite.
std::string fmt(double v, int precision = 2);

// Opens the sequence for its name, frame count, ground truth and scene (InputError if it cannot).
SequenceInfo readSequenceInfo(const std::string& path);

// A finished run read back from `dir` and scored (throws InputError for a missing or bad file).
RunResult loadRun(const Method& method, const std::string& dir, const SequenceInfo& seq);

// report.md, table_3_1.csv, table_3_2.csv, accuracy.csv and figures/ in out_dir; results[s][m]
// is methods[m] on seqs[s]. `preamble` is the report's first paragraph. Returns report.md's path.
std::string writeCompareReport(const std::vector<SequenceInfo>& seqs, const std::vector<Method>& methods,
                               const std::vector<std::vector<RunResult>>& results, int max_frames,
                               const std::string& preamble, const std::string& out_dir);

}  // namespace slamcmp
