#include "eval/app/compare.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/run_files.h"
#include "core/text_file.h"
#include "eval/app/backends.h"
#include "eval/app/compare_plan.h"
#include "eval/app/job_runner.h"
#include "eval/app/run_sequence.h"
#include "eval/report/experiment_plan.h"
#include "eval/report/plot.h"

namespace fs = std::filesystem;

namespace slamcmp {

Method methodOf(const std::string& backend_name, const std::string& mode, const std::string& where) {
  const BackendRegistration& backend = findBackend(backend_name, where);
  const BackendMode& m = findMode(backend, mode, where);
  Method method;
  method.backend = backend.name;
  method.mode = &m == &backend.modes.front() ? "" : m.name;  // the default mode keeps the short label
  method.colour = m.colour;
  method.thesis_method = m.thesis_method;
  return method;
}

std::vector<Method> allMethods() {
  std::vector<Method> methods;
  for (const BackendRegistration& b : backends())
    for (const BackendMode& m : b.modes) methods.push_back(methodOf(b.name, m.name, b.name));
  return methods;
}

std::vector<Method> parseMethods(const std::string& list) {
  std::vector<Method> methods;
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    const std::string where = "--backends " + item;
    // backend[:mode][@init]
    const auto at = item.find('@');
    const std::string name_mode = item.substr(0, at);
    const auto colon = name_mode.find(':');
    const std::string mode = colon == std::string::npos ? "" : name_mode.substr(colon + 1);
    if (colon != std::string::npos && mode.empty()) throw InputError(where, "names no mode");
    Method m = methodOf(name_mode.substr(0, colon), mode, where);
    if (at != std::string::npos) {
      const std::string init = item.substr(at + 1);
      requireTakesInit(findBackend(m.backend, where), where);
      if (init != "board" && init != "groundtruth" && init != "none")
        throw InputError(where, "@ takes board, groundtruth or none, got '" + init + "'");
      if (init != "board") {  // the default start keeps the short label
        m.init = init;
        m.thesis_method.clear();  // the thesis's methods started from the board
        m.colour = shadeColour(m.colour, init == "none" ? 0.45 : -0.45);
      }
    }
    for (const Method& other : methods)
      if (other.label() == m.label())  // both runs would write into one folder
        throw InputError("--backends", "'" + item + "' is listed twice (as " + m.label() + ")");
    methods.push_back(m);
  }
  if (methods.empty()) throw InputError("--backends", "names no back-end");
  return methods;
}

namespace {

// The run's last line in its log ("" if none): its result line, or its error ("slamcmp: ...").
// InputError if the log is a folder (which would read as an empty log) or cannot be opened.
std::string lastLogLine(const std::string& path) {
  std::ifstream in = openTextFile(path);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty() && line.find('\r') == std::string::npos) last = line;
  return last;
}

// A sequence as collect reads it: its ground truth and scene, or, where it cannot be read (moved,
// deleted, a file broken since the plan), its name alone and why. Its runs fail; the others are
// collected.
struct CollectedSequence {
  SequenceInfo info;
  std::string error;  // "" when read
};

CollectedSequence collectSequence(const std::string& path, const std::string& name) {
  try {
    return {readSequenceInfo(path, SequenceImages::NotNeeded), ""};
  } catch (const InputError& e) {
    SequenceInfo info;
    info.path = path;
    info.name = name;
    info.frames = -1;  // not known
    return {info, std::string("its sequence cannot be read: ") + e.what()};
  }
}

// One planned run read back: finished (ok), interrupted (summary.json or its log says so), failed
// (its log's last line, or its sequence unreadable), unfinished (a log and no more: running, or
// killed without a word) or not run (no log).
RunResult collectRun(const Plan& plan, const PlannedRun& planned, const std::string& dir,
                     const CollectedSequence& seq) {
  const Method& method = plan.methods[planned.method];
  const std::string run_dir = (fs::path(dir) / planned.dir).string();
  RunResult r;
  std::error_code ec;
  if (!seq.error.empty()) {
    r.status = "failed";
    r.error = seq.error;
  } else if (fs::exists(fs::path(run_dir) / run_files::kSummary, ec)) {
    try {
      r = loadRun(method, run_dir, seq.info);
      if (r.summary.value("interrupted", false)) {
        r.status = "interrupted";
        r.error = "stopped after " + std::to_string(r.summary.value("frames", 0)) + " frames";
      }
    } catch (const InputError& e) {  // a run whose files cannot be read or scored; a fault of ours still ends compare
      r = RunResult();
      r.status = "failed";
      r.error = e.what();
    }
  } else if (fs::exists(fs::path(dir) / planned.log, ec)) {
    try {
      // A run that failed ended its log on its error ("slamcmp: ..."); one that compare stopped before
      // it wrote anything, on compare's note; one that finished, on its result line. Any other has
      // not finished: still running (a cluster's collect mid-way), or killed without a word.
      const std::string last = lastLogLine((fs::path(dir) / planned.log).string());
      const std::string error_prefix = "slamcmp: ";
      if (last.compare(0, error_prefix.size(), error_prefix) == 0) {
        r.error = last.substr(error_prefix.size());
        // Stopped by Ctrl-C or SIGTERM before it wrote its outputs (while reading its image list).
        const bool stopped =
            r.error.rfind("interrupted", 0) == 0 || r.error.find(": interrupted while") != std::string::npos;
        r.status = stopped ? "interrupted" : "failed";
      } else if (last.rfind(kStoppedByCompare, 0) == 0) {
        r.status = "interrupted";
        r.error = last;
      } else if (last.find(kRunResultMark) != std::string::npos) {  // finished, its summary.json since removed
        r.status = "failed";
        r.error = "no summary.json; its log ends: " + last;
      } else {
        r.status = "unfinished";
        r.error = "no summary.json yet: still running, or stopped without a word (its log ends: " +
                  (last.empty() ? std::string("nothing") : last) + ")";
      }
    } catch (const InputError& e) {  // the log is a folder or unreadable: that is the run's error
      r.status = "failed";
      r.error = e.what();
    }
  } else {
    r.status = "not run";
  }
  r.method = method;
  r.dir = planned.dir;
  r.trial = planned.trial;
  r.sequence = &seq.info;
  return r;
}

std::string absoluteDir(const std::string& dir) { return fs::absolute(dir).lexically_normal().string(); }

// A path the plan wrote inside its own folder (a trial's render, a sequence rendered there), in the
// folder it is collected from: one moved, or copied back from a cluster's scratch.
std::string inCollectedFolder(const std::string& path, const Plan& plan, const std::string& dir) {
  if (plan.dir.empty() || fs::path(plan.dir) == fs::path(dir)) return path;
  const fs::path relative = fs::path(path).lexically_relative(plan.dir);
  if (relative.empty() || *relative.begin() == "..") return path;
  return (fs::path(dir) / relative).string();
}

}  // namespace

size_t planCompare(const CompareOptions& options) {
  const Plan plan = makePlan(options);
  writePlanFiles(plan, absoluteDir(options.out_dir), options.array_tasks);
  return plan.runs.size();
}

std::string collectCompare(const std::string& dir_given, std::vector<UnfinishedRun>* unfinished) {
  const std::string dir = absoluteDir(dir_given);
  const std::string plan_path = dir + "/plan.json";
  std::error_code ec;
  if (!fs::exists(plan_path, ec))
    throw InputError(plan_path, "missing: --collect takes the folder that compare --plan wrote");
  const Plan plan = planFromJson(readJsonFile(plan_path), plan_path);
  std::vector<SequenceInfo> seqs;
  // Only the runs are read: the images may be gone (deleted to free a cluster's disk).
  for (size_t s = 0; s < plan.sequences.size(); ++s)
    seqs.push_back(collectSequence(inCollectedFolder(plan.sequences[s], plan, dir), plan.sequence_names[s]).info);
  std::map<std::string, CollectedSequence> trial_seqs;  // each trial's own ground truth and scene
  std::vector<RunResult> runs;
  std::vector<UnfinishedRun> not_finished;
  for (const PlannedRun& planned : plan.runs) {
    const std::string sequence_path = inCollectedFolder(planned.sequence_path, plan, dir);
    auto it = trial_seqs.find(sequence_path);
    if (it == trial_seqs.end())
      it = trial_seqs.emplace(sequence_path, collectSequence(sequence_path, plan.sequence_names[planned.sequence])).first;
    runs.push_back(collectRun(plan, planned, dir, it->second));
    if (!runs.back().finished()) not_finished.push_back({planned.dir, runs.back().status, runs.back().error});
  }
  // An earlier collect's figures are redrawn, or gone; a user's own files in figures/ stay. Its
  // report goes first: one stopped while drawing (Ctrl-C) leaves no old report beside new tables.
  for (const std::string& figure : linkedFigures(dir)) fs::remove(fs::path(dir) / figure, ec);
  for (const std::string& file : compareReportFiles()) fs::remove(fs::path(dir) / file, ec);
  fs::create_directories(dir + "/figures", ec);
  if (ec) throw InputError(dir + "/figures", "cannot be created: " + ec.message());
  if (unfinished) *unfinished = not_finished;
  return writeCompareReport(plan, seqs, runs, dir);
}

void sayCompareReport(const std::string& dir, const std::string& report, const std::vector<UnfinishedRun>& unfinished) {
  std::cout << "report: " << report;
  if (!unfinished.empty()) std::cout << " (" << unfinished.size() << " runs not finished: see its last section)";
  std::cout << "\n";
  int failed = 0;
  for (const UnfinishedRun& run : unfinished)
    if (run.status == "failed") {
      std::cerr << "slamcmp: " << (std::filesystem::path(dir) / run.dir).string() << ": failed: " << run.error << "\n";
      ++failed;
    }
  // Runs still to come (a cluster's queue) are no error, but a report short of them is said so
  // where scripts look, beside any that failed.
  if (const size_t others = unfinished.size() - static_cast<size_t>(failed); others > 0)
    std::cerr << "slamcmp: warning: " << report << ": " << others
              << " run(s) not finished (not run, running or interrupted); the report marks them\n";
  if (failed > 0)
    throw InputError(report, std::to_string(failed) + " run(s) failed (the lines above); the report marks them");
}

std::string runCompare(const CompareOptions& options, std::vector<UnfinishedRun>* unfinished) {
  const Plan plan = makePlan(options);
  const std::string dir = absoluteDir(options.out_dir);
  writePlanFiles(plan, dir, options.array_tasks);
  const bool finished = runPlannedJobs(plan, dir, options.jobs);
  std::vector<UnfinishedRun> not_finished;
  const std::string report = collectCompare(dir, &not_finished);
  if (!finished)
    throw Interrupted("interrupted: " + report + " marks the " + std::to_string(not_finished.size()) +
                      " runs not finished");
  if (unfinished) *unfinished = not_finished;
  return report;
}

}  // namespace slamcmp
