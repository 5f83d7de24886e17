#pragma once
// compare's report: every run read back from its folder (summary.json, frames.csv,
// trajectory.txt, map.ply, nees.csv), scored, and written as report.md, CSV tables and figures. It reads
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
#include "eval/metrics/monte_carlo_nees.h"
#include "eval/metrics/nees.h"
#include "eval/metrics/run_errors.h"

namespace slamcmp {

// A back-end with an optional mode, written "cslam", "cslam:calibration", "monoslam"; its colour and
// thesis column come from the back-end registry.
// In a sweep (compare --set), each setting of a back-end's swept options is a Method of its own:
// "cslam features.max_features=50".
struct Method {
  std::string backend;
  std::string mode;                // "" = the back-end's default mode
  std::string colour = "#9467bd";  // figure colour
  std::string thesis_method;       // the thesis's Table 3.2 column it stands beside ("" = none)
  std::string setting;             // "" or the swept options' values: "features.max_features=50 ..."
  std::string init;                // "" = the back-end's default start (the board), or run's --init: "none", ...
  std::string config;              // "" = the back-end's defaults, or the name of compare's --config file
  std::string base() const { return (mode.empty() ? backend : backend + ":" + mode) + (init.empty() ? "" : "@" + init); }
  // The back-end with its option file: what a sweep varies the setting of.
  std::string configured() const { return config.empty() ? base() : base() + " config=" + config; }
  std::string label() const { return setting.empty() ? configured() : configured() + " " + setting; }
  std::string slug() const;        // a folder name: "cslam-calibration", "cslam-features.max_features=50"
};

struct SequenceInfo {
  std::string path, name;
  int frames = 0;
  std::optional<Trajectory> groundtruth;
  std::optional<SceneGeometry> scene;  // synthetic sequences: the true surfaces (scene.yaml)
};

// One run (a method on one trial of a sequence), as read back from its output folder.
struct RunResult {
  Method method;
  std::string dir;
  int trial = 1;
  const SequenceInfo* sequence = nullptr;  // the trial's sequence (its own ground truth and scene)
  std::string status = "ok";  // ok | failed | interrupted | unfinished | not run
  std::string error;          // why it did not finish (the run's last message, or what stopped it), if said
  nlohmann::json summary;
  std::vector<FrameRow> frames;
  Trajectory trajectory;
  std::optional<RunErrors> errors;
  std::vector<TimedNees> nees;           // nees.csv, when the run scored its covariances
  std::vector<MapPoint> map;             // map.ply, read back when the sequence has a scene
  std::optional<MapEvaluation> map_errors;
  bool finished() const { return status == "ok"; }  // its numbers count; every other status has none
};

// A number for a table: fixed with `precision` decimals, "-" when not finite.
std::string fmt(double v, int precision = 2);

// Opens the sequence for its name, frame count, ground truth and scene (InputError if it cannot).
// `images`: its images are checked too (a plan's, whose runs need them); a collect reads the runs
// without them (SequenceOpenOptions::read_images).
enum class SequenceImages { Checked, NotNeeded };
SequenceInfo readSequenceInfo(const std::string& path, SequenceImages images);

// A finished run read back from `dir` and scored (throws InputError for a missing or bad file).
RunResult loadRun(const Method& method, const std::string& dir, const SequenceInfo& seq);

struct Plan;

// The plan's runs of sequence s and method m (plan.runs[k] is runs[k]), in trial order.
std::vector<const RunResult*> cellRuns(const Plan& plan, const std::vector<RunResult>& runs, size_t s, size_t m);
// A results column's numbers over the cell's finished runs (runValue; not finite left out).
std::vector<double> cellValues(const std::vector<const RunResult*>& cell, const std::string& column);

// Bar-Shalom's test over the trials of sequence s and method m (plan.runs[k] is runs[k]): their
// finished runs on a rendered trial (seed_kind "render") that scored their covariances (nees.csv);
// nothing with fewer than 2.
std::optional<MonteCarloNees> trialsMonteCarloNees(const Plan& plan, const std::vector<RunResult>& runs, size_t s,
                                                   size_t m);

// The files writeCompareReport writes in out_dir, beside figures/.
const std::vector<std::string>& compareReportFiles();
// The figures an earlier report in out_dir links (paths relative to out_dir, under figures/): what
// a new report may remove of figures/, where a user may keep files of their own.
std::vector<std::string> linkedFigures(const std::string& out_dir);

// report.md, results.csv (one row a run), table_3_1.csv, table_3_2.csv and figures/ in out_dir.
// runs[k] is plan.runs[k] read back; seqs[s] the plan's given sequence s. Everything written
// depends on the plan and the runs only (not on where or when they ran). Returns report.md's path.
std::string writeCompareReport(const Plan& plan, const std::vector<SequenceInfo>& seqs,
                               const std::vector<RunResult>& runs, const std::string& out_dir);

}  // namespace slamcmp
