#include "eval/app/compare_plan.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <sstream>

#include "core/error.h"
#include "core/interrupt.h"
#include "core/run_files.h"
#include "core/text_file.h"
#include "core/yaml.h"
#include "datasets/synth_sequence.h"
#include "eval/app/backends.h"
#include "eval/app/job_runner.h"
#include "eval/app/run_sequence.h"
#include "eval/report/plot.h"

namespace fs = std::filesystem;

namespace slamcmp {

namespace {

// The slamcmp binary running now, which the jobs run too.
std::string selfExecutable() {
  std::error_code ec;
  const fs::path self = fs::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot find the slamcmp binary (/proc/self/exe): " + ec.message());
  return self.string();
}

struct Sweep {
  std::string key;                  // "cslam.features.max_features"
  std::string backend;              // "cslam"
  std::vector<std::string> values;  // "50", "100", "200"
};

// One --config: an option file (as `run --config` reads it) and the back-ends it has a section for;
// or the back-ends' defaults.
struct OptionFile {
  std::string path;   // absolute; "" = the defaults
  std::string name;   // the file's stem, which labels its methods; "" for the defaults
  std::vector<std::string> backends;
};

constexpr const char* kDefaultsConfig = "defaults";

// --config FILE ... checked: files that open, sections that name back-ends, each file useful to one
// of the methods, no file twice (the values a file sets are checked with the sweeps', in makePlan).
std::vector<OptionFile> parseOptionFiles(const std::vector<std::string>& given, const std::vector<Method>& methods) {
  std::vector<OptionFile> files;
  for (const std::string& text : given) {
    OptionFile file;
    if (text != kDefaultsConfig) {
      const YamlFile yaml(text);
      file.path = fs::canonical(text).string();  // the file YamlFile opened, through any link
      file.name = fs::path(text).stem().string();
      for (const BackendRegistration* backend : configBackends(yaml, text)) file.backends.push_back(backend->name);
      if (std::none_of(methods.begin(), methods.end(), [&](const Method& m) {
            return std::find(file.backends.begin(), file.backends.end(), m.backend) != file.backends.end();
          }))
        throw InputError("--config " + text, "has no section for a back-end among --backends");
    }
    for (const OptionFile& other : files)
      if (other.path == file.path) throw InputError("--config " + text, "is given twice");
    files.push_back(std::move(file));
  }
  return files;
}

// The option files a back-end runs with: those with its section; and its defaults too when
// `defaults` is among them, or when none has its section.
std::vector<OptionFile> optionFilesOf(const std::string& backend, const std::vector<OptionFile>& files) {
  std::vector<OptionFile> own;
  bool defaults = false;
  for (const OptionFile& file : files) {
    if (file.path.empty()) defaults = true;
    if (std::find(file.backends.begin(), file.backends.end(), backend) != file.backends.end()) own.push_back(file);
  }
  if (defaults || own.empty()) own.insert(own.begin(), OptionFile{});
  return own;
}

// The folders a compare makes in its own: the runs, their logs, the report's figures.
constexpr const char* kExperimentFolders[] = {"runs", "logs", "figures"};

// Where trial k's render of a given sequence goes.
fs::path trialRenderFolder(const fs::path& dir, int trial) { return dir / "sequences" / ("seed" + std::to_string(trial)); }

// A path an earlier plan.json gives for one of its runs: kept only if it names an entry of `folder`
// (runs/NAME, logs/NAME.log), so that an edited plan cannot remove anything else.
bool isOwnEntry(const nlohmann::json& path, const char* folder) {
  return path.is_string() && isEntryOf(path.get<std::string>(), folder);
}

// An earlier compare's folder (its plan.json): what it wrote goes, or the new report would sit
// beside the old experiment's (a plan alone leaves no report to read for the new one). Only what
// it wrote: its runs and logs as its plan.json lists them, the figures its report links, its
// report files, and the folders trialRenderFolder names, not through a link, and not one that is
// or holds a sequence given now (reproduce renders tv1..tv4 into sequences/: its second run into
// the same folder found them gone). A user's own files in runs/, logs/ or figures/ (a standalone
// `slamcmp run`'s default runs/SEQ-BACKEND, a figure for a paper) stay.
void removeEarlierExperiment(const fs::path& dir, const std::vector<std::string>& given) {
  const std::string plan_path = (dir / "plan.json").string();
  const nlohmann::json earlier = readJsonFile(plan_path);
  if (!earlier.is_object() || !earlier.contains("runs") || !earlier["runs"].is_array())
    throw InputError(plan_path + ": runs", "missing: not an earlier compare's plan; give another --out");
  std::error_code ec;
  for (const nlohmann::json& run : earlier["runs"]) {
    if (!run.is_object()) continue;
    if (run.contains("dir") && isOwnEntry(run["dir"], "runs")) fs::remove_all(dir / run["dir"].get<std::string>(), ec);
    if (run.contains("log") && isOwnEntry(run["log"], "logs")) fs::remove(dir / run["log"].get<std::string>(), ec);
  }
  for (const std::string& figure : linkedFigures(dir.string())) fs::remove(dir / figure, ec);
  // Its Slurm tasks' logs (slurm.sbatch's --output: slurm-JOB_TASK.out).
  const std::regex slurm_log(R"(slurm-[0-9]+_[0-9]+\.out)");
  std::vector<fs::path> slurm_logs;
  for (fs::directory_iterator it(dir / "logs", ec), end; !ec && it != end; it.increment(ec))
    if (std::regex_match(it->path().filename().string(), slurm_log)) slurm_logs.push_back(it->path());
  for (const fs::path& log : slurm_logs) fs::remove(log, ec);
  for (const std::string& file : compareReportFiles()) fs::remove(dir / file, ec);
  std::vector<fs::path> renders;
  for (fs::directory_iterator it(dir / "sequences", ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::error_code link_ec;
    if (name.size() > 4 && name.size() < 14 && name.find_first_not_of("0123456789", 4) == std::string::npos &&
        it->path() == trialRenderFolder(dir, std::stoi(name.substr(4))) && !it->is_symlink(link_ec))
      renders.push_back(it->path());
  }
  for (const fs::path& render : renders) {
    const std::string folder = fs::weakly_canonical(render, ec).string();
    const bool holds_given = std::any_of(given.begin(), given.end(), [&](const std::string& sequence) {
      const std::string path = fs::weakly_canonical(sequence, ec).string();
      return path == folder || path.rfind(folder + "/", 0) == 0;
    });
    if (!holds_given) fs::remove_all(render, ec);
  }
  fs::remove(dir / "sequences", ec);  // when empty
}

// "SECTION.KEY=V1,V2,..." checked: a back-end among the methods, an option it has, values it takes
// on top of each of its option files.
Sweep parseSweep(const std::string& text, const std::vector<Method>& methods, const std::vector<OptionFile>& files) {
  const std::string where = "--set " + text;
  const OptionSetting setting =
      parseOptionSetting(text, "SECTION.KEY=V1,V2,..., e.g. cslam.features.max_features=100,150,200");
  Sweep sweep{setting.backend->name + "." + setting.key, setting.backend->name, {}};
  const BackendRegistration& backend = *setting.backend;
  if (std::none_of(methods.begin(), methods.end(), [&](const Method& m) { return m.backend == backend.name; }))
    throw InputError(where, backend.name + " is not among --backends");
  const std::vector<OptionFile> own_files = optionFilesOf(backend.name, files);
  std::stringstream values(setting.value);
  std::vector<nlohmann::json> loaded;  // the options each value gives: 200 and 0200 are one setting
  for (std::string v; std::getline(values, v, ',');) {
    if (v.empty()) throw InputError(where, "has an empty value");
    if (std::find(sweep.values.begin(), sweep.values.end(), v) != sweep.values.end())
      throw InputError(where, "lists '" + v + "' twice");
    nlohmann::json options;
    for (const OptionFile& file : own_files) {
      try {  // the option exists and takes the value, with the file's (or the defaults') other options
        const auto with_value = loadBackendOptions(backend, file.path, {sweep.key + "=" + v});
        if (options.is_null()) options = with_value->toJson();
      } catch (const InputError& e) {
        throw InputError(where, "value " + v + (file.path.empty() ? "" : " with --config " + file.path) + ": " + e.what());
      }
    }
    if (const auto same = std::find(loaded.begin(), loaded.end(), options); same != loaded.end())
      throw InputError(where, "lists '" + sweep.values[static_cast<size_t>(same - loaded.begin())] + "' and '" + v +
                                  "', the same value");
    loaded.push_back(std::move(options));
    sweep.values.push_back(v);
  }
  if (sweep.values.empty()) throw InputError(where, "gives no value");
  return sweep;
}

// The method's settings: every combination of its back-end's sweeps, in the order given.
std::vector<std::vector<std::string>> settingsOf(const Method& method, const std::vector<Sweep>& sweeps) {
  std::vector<std::vector<std::string>> grid{{}};
  for (const Sweep& sweep : sweeps) {
    if (sweep.backend != method.backend) continue;
    std::vector<std::vector<std::string>> next;
    for (const auto& partial : grid)
      for (const std::string& v : sweep.values) {
        next.push_back(partial);
        next.back().push_back(sweep.key + "=" + v);
      }
    grid = next;
  }
  return grid;
}

std::string settingLabel(const std::vector<std::string>& sets) {
  std::string label;
  for (const std::string& set : sets) label += (label.empty() ? "" : " ") + set.substr(set.find('.') + 1);
  return label;
}

}  // namespace

std::string shellQuoted(const std::string& s) {
  if (!s.empty() && s.find_first_not_of("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-+=./:,@%") ==
                        std::string::npos)
    return s;
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

Plan makePlan(const CompareOptions& options) {
  if (options.sequences.empty()) throw InputError("--sequence", "give at least one sequence");
  if (options.max_frames == 0) throw InputError("--max-frames 0", "nothing to run");
  if (options.trials < 1) throw InputError("--trials", "must be at least 1, got " + std::to_string(options.trials));
  if (options.methods.empty()) throw InputError("--backends", "names no back-end");
  const std::vector<OptionFile> files = parseOptionFiles(options.configs, options.methods);
  std::vector<Sweep> sweeps;
  Plan plan;
  for (const std::string& text : options.sets) {
    sweeps.push_back(parseSweep(text, options.methods, files));
    for (const Sweep& other : std::vector<Sweep>(sweeps.begin(), sweeps.end() - 1))
      if (other.key == sweeps.back().key) throw InputError("--set " + text, "sweeps " + other.key + " twice");
    plan.swept_keys.push_back(sweeps.back().key);
  }
  const fs::path dir = fs::absolute(options.out_dir).lexically_normal();
  plan.dir = dir.string();
  std::vector<SequenceInfo> infos;
  for (const std::string& path : options.sequences) {
    SequenceInfo info = readSequenceInfo(path, SequenceImages::Checked);
    for (const auto& other : infos)
      if (other.name == info.name) throw InputError(path, "two sequences are named '" + info.name + "'");
    plan.sequences.push_back(fs::absolute(path).lexically_normal().string());
    plan.sequence_names.push_back(info.name);
    infos.push_back(std::move(info));
  }
  for (const OptionFile& file : files)
    if (!file.path.empty()) plan.configs.push_back(file.path);
  std::vector<std::vector<std::string>> method_sets;  // each method's --set arguments
  std::vector<std::string> method_configs;            // and its option file
  for (const Method& method : options.methods) {
    const auto settings = settingsOf(method, sweeps);
    const auto own_files = optionFilesOf(method.backend, files);
    const size_t n = own_files.size() * settings.size();
    for (size_t k = 0; k < n; ++k) {
      const OptionFile& file = own_files[k / settings.size()];
      const std::vector<std::string>& sets = settings[k % settings.size()];
      try {  // the file with the sweeps' values together (each was checked alone)
        loadBackendOptions(findBackend(method.backend), file.path, sets);
      } catch (const InputError& e) {
        std::string where;
        for (const std::string& set : sets) where += (where.empty() ? "--set " : " --set ") + set;
        throw InputError(where, e.what());
      }
      Method m = method;
      m.config = file.name;
      m.setting = settingLabel(sets);
      // Shades from darker to lighter keep every setting of one back-end near its colour.
      if (n > 1) m.colour = shadeColour(method.colour, -0.45 + 0.9 * k / (n - 1));
      plan.methods.push_back(m);
      method_sets.push_back(sets);
      method_configs.push_back(file.path);
    }
  }
  for (size_t a = 0; a < plan.methods.size(); ++a)
    for (size_t b = 0; b < a; ++b)
      if (plan.methods[a].slug() == plan.methods[b].slug())
        throw InputError("compare", "`" + plan.methods[b].label() + "` and `" + plan.methods[a].label() +
                                        "` would write the same run folders (" + plan.methods[a].slug() +
                                        "): rename an option file or a value");
  plan.trials = options.trials;
  plan.max_frames = options.max_frames;
  // The trials' info.yaml read too before a folder is made: a refused compare, as a refused run,
  // leaves --out as it found it.
  std::vector<std::optional<SynthOptions>> synths;
  for (const std::string& path : plan.sequences) {
    std::optional<SynthOptions> synth = options.trials > 1 ? readSynthInfo(path) : std::nullopt;
    // A render copied and changed (resized, cut, another target) keeps its info.yaml: new renders
    // from it would not be trials of that sequence, so it reruns as real data does.
    if (synth) {
      if (const std::string differs = differenceFromItsRender(path, *synth); !differs.empty()) {
        std::cerr << path << ": warning: not what its info.yaml renders (" << differs
                  << "): its trials rerun the back-ends with --seed k, not new renders\n";
        synth.reset();
      }
    }
    synths.push_back(std::move(synth));
  }
  // Trial k is rendered with seed k: two given renders that differ in their seed alone share every
  // trial, and their rows would be the same renders under two names.
  if (options.trials > 1)
    for (size_t s = 0; s < synths.size(); ++s)
      for (size_t t = s + 1; t < synths.size(); ++t) {
        if (!synths[s] || !synths[t]) continue;
        SynthOptions a = *synths[s], b = *synths[t];
        a.seed = b.seed = 0;
        for (SynthOptions* o : {&a, &b})  // as the trials render them
          o->frames = options.max_frames > 0 ? std::min(o->frameCount(), options.max_frames) : o->frameCount();
        if (optionsToJson(a) == optionsToJson(b))
          std::cerr << plan.sequences[t] << ": warning: the same render as " << plan.sequences[s]
                    << " but for its seed: trial k of each is rendered with seed k, so their " << options.trials
                    << " trials are the same sequences (give one of them)\n";
      }

  std::error_code ec;
  if (fs::exists(dir / "plan.json", ec)) removeEarlierExperiment(dir, plan.sequences);
  for (const char* sub : kExperimentFolders) {
    fs::create_directories(dir / sub, ec);
    if (ec) throw InputError(options.out_dir, "output folder cannot be created: " + ec.message());
  }
  const std::string slamcmp = options.slamcmp.empty() ? selfExecutable() : fs::absolute(options.slamcmp).string();
  for (size_t s = 0; s < plan.sequences.size(); ++s) {
    const std::optional<SynthOptions>& synth = synths[s];
    for (int trial = 1; trial <= options.trials; ++trial) {
      std::string sequence_path = plan.sequences[s];
      std::string seed_kind;
      if (options.trials > 1) seed_kind = synth ? "render" : "backend";
      if (synth) {
        // The trial's sequence: the given one's options with seed `trial`, only the frames a run uses.
        SynthOptions render = *synth;
        render.seed = trial;
        render.frames = options.max_frames > 0 ? std::min(synth->frameCount(), options.max_frames) : synth->frameCount();
        if (synth->seed != trial || synth->frameCount() < render.frames) {
          sequence_path = (trialRenderFolder(dir, trial) / plan.sequence_names[s]).string();
          std::cerr << "rendering " << sequence_path << " (" << render.frames << " frames)\n";
          writeSyntheticSequence(render, sequence_path);
          if (interrupted()) throw Interrupted("interrupted while rendering " + sequence_path + "; nothing ran");
        }
      }
      for (size_t m = 0; m < plan.methods.size(); ++m) {
        PlannedRun run;
        run.sequence = s;
        run.method = m;
        run.trial = trial;
        run.seed_kind = seed_kind;
        if (!seed_kind.empty()) run.seed = trial;
        run.sequence_path = sequence_path;
        const std::string name = plan.sequence_names[s] + "-" + plan.methods[m].slug() +
                                 (options.trials > 1 ? "-t" + std::to_string(trial) : "");
        run.dir = "runs/" + name;
        run.log = "logs/" + name + ".log";
        run.sets = method_sets[m];
        run.config = method_configs[m];
        const Method& method = plan.methods[m];
        run.argv = {slamcmp, "run", "--backend", method.backend};
        if (!method.mode.empty()) run.argv.insert(run.argv.end(), {"--mode", method.mode});
        if (!method.init.empty()) run.argv.insert(run.argv.end(), {"--init", method.init});
        run.argv.insert(run.argv.end(), {"--sequence", sequence_path, "--out", (dir / run.dir).string()});
        if (options.max_frames > 0) run.argv.insert(run.argv.end(), {"--max-frames", std::to_string(options.max_frames)});
        if (seed_kind == "backend") run.argv.insert(run.argv.end(), {"--seed", std::to_string(trial)});
        if (!run.config.empty()) run.argv.insert(run.argv.end(), {"--config", run.config});
        for (const std::string& set : run.sets) run.argv.insert(run.argv.end(), {"--set", set});
        // An earlier compare's runs are gone (removeEarlierExperiment): a folder of this name is a
        // user's (a standalone `slamcmp run`'s default runs/SEQ-BACKEND), not compare's to replace.
        if (fs::exists(dir / run.dir, ec))
          throw InputError((dir / run.dir).string(), "holds a run no earlier compare planned (a standalone `slamcmp "
                                                     "run`'s?): compare would replace it; move it, or give another --out");
        fs::remove(dir / run.log, ec);
        plan.runs.push_back(std::move(run));
      }
    }
  }
  return plan;
}

std::string jobLine(const PlannedRun& run, const std::string& dir) {
  std::string line;
  for (const std::string& a : run.argv) line += (line.empty() ? "" : " ") + shellQuoted(a);
  const std::string log = shellQuoted((fs::path(dir) / run.log).string());
  const std::string summary = shellQuoted((fs::path(dir) / run.dir / run_files::kSummary).string());
  // A run that died on a signal (a crash on a node) ends its log saying so, as compare's own runner
  // does, unless it said why itself: collect calls a log without either still running.
  return line + " > " + log + " 2>&1 || { s=$?; if [ \"$s\" -gt 128 ] && [ ! -e " + summary + " ] && ! tail -n 1 " +
         log + " | grep -q '^slamcmp: '; then echo \"" + kEndedOnSignal + "$((s - 128))\" >> " + log +
         "; fi; exit \"$s\"; }";
}

void writePlanFiles(const Plan& plan, const std::string& dir, int array_tasks) {
  auto write = [&](const std::string& name, const std::string& text) {
    const std::string path = (fs::path(dir) / name).string();
    std::ofstream out(path);
    out << text;
    if (!out) throw InputError(path, "cannot be written");
  };
  write("plan.json", planToJson(plan).dump(1) + "\n");
  std::string jobs;
  for (const PlannedRun& run : plan.runs) jobs += jobLine(run, dir) + "\n";
  write("jobs.txt", jobs);
  const size_t tasks = std::min(plan.runs.size(), static_cast<size_t>(std::max(array_tasks, 1)));
  const std::string jobs_path = shellQuoted((fs::path(dir) / "jobs.txt").string());
  // Slurm expands %A, %a, ... in --output: a '%' of the folder's own is written '%%'.
  std::string log_dir;
  for (const char c : (fs::path(dir) / "logs").string()) log_dir += c == '%' ? std::string("%%") : std::string(1, c);
  std::ostringstream sbatch;
  sbatch << "#!/bin/bash\n"
         << "# slamcmp compare --plan: a Slurm array job over jobs.txt (one `slamcmp run` a line): task k runs\n"
         << "# lines k, k + " << tasks << ", k + " << 2 * tasks << ", ... (`sbatch --array=K` reruns task K's).\n"
         << "# Submit with `sbatch " << shellQuoted((fs::path(dir) / "slurm.sbatch").string())
         << "`; once every task is done, `slamcmp compare --collect " << shellQuoted(dir) << "`.\n"
         << "#SBATCH --job-name=slamcmp\n"
         << "#SBATCH --array=1-" << tasks << "\n"
         << "#SBATCH --ntasks=1\n"
         << "#SBATCH --cpus-per-task=1\n"
         // Slurm splits a directive at spaces unless the value is in double quotes.
         << "#SBATCH --output=\"" << log_dir << "/slurm-%A_%a.out\"\n"
         // A wider --array than written would run some lines twice, at once, into the same folders.
         << "if [ \"${SLURM_ARRAY_TASK_ID:-1}\" -lt 1 ] || [ \"${SLURM_ARRAY_TASK_ID:-1}\" -gt " << tasks << " ]; then\n"
         << "  echo \"slurm.sbatch: task ${SLURM_ARRAY_TASK_ID} of an array written for 1-" << tasks
         << " (compare --plan --array-tasks)\" >&2\n"
         << "  exit 2\n"
         << "fi\n"
         << "status=0\n"
         << "for k in $(seq \"${SLURM_ARRAY_TASK_ID:-1}\" " << tasks << " " << plan.runs.size() << "); do\n"
         << "  line=$(sed -n \"${k}p\" " << jobs_path << ")\n"
         << "  /bin/sh -c \"$line\" || status=$?\n"
         << "done\n"
         << "exit \"$status\"\n";
  write("slurm.sbatch", sbatch.str());
}

}  // namespace slamcmp
