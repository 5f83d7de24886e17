// Writes docs/benchmarks.md from Google Benchmark's JSON (bench_stages, bench_monoslam,
// bench_tracking) and scripts/bench.sh's whole-run timings, beside the thesis's Table 3.2 as
// eval/thesis_tables holds it (the one copy of the thesis's numbers). It names no back-end: the
// rows are the BM_Track/<backend>[/<mode>] entries bench_tracking wrote (each labelled with its
// Table 3.2 column, from the registry) and the runs bench.sh timed.
//
//   bench_report --stages S.json --monoslam M.json --tracking T.json --runs RUNS.tsv
//                --targets benchmarks/targets.txt --preset tv1 --machine "..." --out docs/benchmarks.md
//
// RUNS.tsv: one line per timed `slamcmp run`: "<backend>[/<mode>] <cores> <wall s> <user + system s>".
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/statistics.h"
#include "eval/report/thesis_tables.h"

namespace slamcmp {
namespace {

struct Result {
  double median = 0;  // CPU time, in `unit`
  std::string unit;
  std::string label;  // bench_tracking: the thesis's Table 3.2 column ("" = none)
  std::map<std::string, double> counters;
  std::string error;
  bool from_aggregate = false;
};

// name -> median over repetitions (or the single run), in the order the file lists them.
std::vector<std::pair<std::string, Result>> readBenchmarks(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  std::stringstream text;
  text << in.rdbuf();
  // Google Benchmark writes NaN and inf (e.g. the spread of a counter that is always 0), which
  // JSON does not have.
  static const std::regex kNotJson(R"(:\s*-?(nan|NaN|inf|Infinity)\b)");
  const nlohmann::json j = nlohmann::json::parse(std::regex_replace(text.str(), kNotJson, ": null"));
  std::vector<std::pair<std::string, Result>> out;
  std::map<std::string, size_t> index;
  static const std::vector<std::string> kNotCounters = {
      "name", "family_index", "per_family_instance_index", "run_name", "run_type", "repetitions",
      "repetition_index", "threads", "iterations", "real_time", "cpu_time", "time_unit", "aggregate_name",
      "aggregate_unit", "error_occurred", "error_message"};
  for (const auto& b : j.at("benchmarks")) {
    std::string name = b.value("run_name", b.at("name").get<std::string>());
    const size_t min_time = name.find("/min_time:");  // a benchmark's own MinTime, not part of its name
    if (min_time != std::string::npos) name.erase(min_time);
    const bool aggregate = b.value("run_type", "iteration") == "aggregate";
    if (aggregate && b.value("aggregate_name", "") != "median") continue;
    auto it = index.find(name);
    if (it == index.end()) {
      it = index.emplace(name, out.size()).first;
      out.emplace_back(name, Result{});
    }
    Result& r = out[it->second].second;
    if (b.value("error_occurred", false)) {
      r.error = b.value("error_message", "error");
      continue;
    }
    if (r.from_aggregate && !aggregate) continue;  // the median stands over any repetition
    r.from_aggregate = aggregate;
    r.median = b.at("cpu_time").get<double>();
    r.unit = b.at("time_unit").get<std::string>();
    r.label = b.value("label", "");
    for (const auto& [key, value] : b.items())
      if (value.is_number() && std::find(kNotCounters.begin(), kNotCounters.end(), key) == kNotCounters.end())
        r.counters[key] = value.get<double>();
  }
  return out;
}

double toMs(const Result& r) {
  if (r.unit == "ns") return r.median * 1e-6;
  if (r.unit == "us") return r.median * 1e-3;
  if (r.unit == "s") return r.median * 1e3;
  return r.median;
}

std::string fixed(double v, int digits) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

// Three significant figures or so, for times from nanoseconds to seconds.
std::string figure(double v) { return fixed(v, v >= 100 ? 0 : v >= 10 ? 1 : v >= 1 ? 2 : 3); }

std::string counters(const Result& r) {
  std::string s;
  for (const auto& [key, value] : r.counters) {
    if (key == "frames_per_s") continue;
    s += (s.empty() ? "" : ", ") + key + " " + figure(value);
  }
  return s;
}

void stageTable(std::ostream& out, const std::vector<std::pair<std::string, Result>>& results) {
  out << "| benchmark | median | per iteration |\n|---|---|---|\n";
  for (const auto& [name, r] : results) {
    if (!r.error.empty()) {
      out << "| " << name << " | skipped: " << r.error << " | |\n";
      continue;
    }
    out << "| " << name << " | " << figure(r.median) << " " << r.unit << " | " << counters(r) << " |\n";
  }
}

const Result* find(const std::vector<std::pair<std::string, Result>>& results, const std::string& name) {
  for (const auto& [n, r] : results)
    if (n == name && r.error.empty()) return &r;
  return nullptr;
}

struct Target {
  std::string ms_per_frame = "-";  // as the table shows it: "-" for none
  double run_over_decode = NAN;    // NaN for none
};

// benchmarks/targets.txt: name -> targets.
std::map<std::string, Target> readTargets(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  std::map<std::string, Target> targets;
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    std::istringstream fields(line);
    std::string name, ms, ratio, note;
    if (!(fields >> name) || name[0] == '#') continue;
    const auto isTarget = [](const std::string& v) {
      char* end = nullptr;
      return v == "-" || (std::strtod(v.c_str(), &end) > 0 && !*end);
    };
    if (!(fields >> ms >> ratio) || !isTarget(ms) || !isTarget(ratio))
      throw std::runtime_error(path + ":" + std::to_string(n) + ": expected 'name ms ratio [note]', '-' for no target");
    std::getline(fields >> std::ws, note);
    Target& t = targets[name];
    if (ms != "-") t.ms_per_frame = "< " + ms + (note.empty() ? "" : " (" + note + ")");
    if (ratio != "-") t.run_over_decode = std::strtod(ratio.c_str(), nullptr);
  }
  return targets;
}

int run(int argc, char** argv) {
  std::map<std::string, std::string> args;
  for (int i = 1; i + 1 < argc; i += 2) args[argv[i]] = argv[i + 1];
  for (const char* key : {"--stages", "--monoslam", "--tracking", "--runs", "--targets", "--preset", "--machine", "--out"})
    if (!args.count(key)) {
      std::cerr << "bench_report: missing " << key << "\n";
      return 2;
    }
  const auto stages = readBenchmarks(args["--stages"]);
  const auto monoslam = readBenchmarks(args["--monoslam"]);
  const auto tracking = readBenchmarks(args["--tracking"]);
  const auto targets = readTargets(args["--targets"]);
  const std::string preset = args["--preset"];
  const auto thesis = thesisVideo(preset);

  std::ostringstream out;
  out << "# Benchmarks\n\nWritten by `scripts/bench.sh` (Release, Google Benchmark, medians of CPU time over "
         "repetitions, each benchmark pinned to one core, OpenCV on one thread, image decoding excluded "
         "unless named). "
      << args["--machine"] << "\n\n";

  out << "## Per frame, rendered " << preset
      << " (bench_tracking: its first 120 frames, or SLAMCMP_BENCH_FRAMES)\n\n"
      << "| back-end | ms per frame (median) | target | thesis Table 3.2 column | thesis, " << preset
      << " (ms) | thesis / here |\n|---|---|---|---|---|---|\n";
  const std::string kTrack = "BM_Track/";
  for (const auto& [name, r] : tracking) {
    if (name.rfind(kTrack, 0) != 0 || !r.error.empty()) continue;
    const std::string what = name.substr(kTrack.size());
    std::string label = what;
    std::replace(label.begin(), label.end(), '/', ' ');
    const auto target = targets.find(what);
    const double ms = toMs(r);
    const double thesis_ms = thesis && !r.label.empty() ? thesisMs(*thesis, r.label) : NAN;
    out << "| " << label << " | " << figure(ms) << " | " << (target == targets.end() ? "-" : target->second.ms_per_frame)
        << " | " << (r.label.empty() ? "-" : r.label) << " | " << (std::isnan(thesis_ms) ? "-" : fixed(thesis_ms, 2))
        << " | " << (std::isnan(thesis_ms) ? "-" : fixed(thesis_ms / ms, 0) + "x") << " |\n";
  }
  if (const Result* r = find(tracking, "BM_DecodeFrame"))
    out << "| decoding one frame (PNG) | " << figure(toMs(*r)) << " | | | | |\n";
  out << "\nThe thesis's column is the one each back-end's registration stands it beside; the thesis "
         "measured on an Athlon 64 X2 dual core (2009), unoptimised, its videos rather than these "
         "renders.\n\n";

  // Whole runs against decoding alone.
  std::ifstream runs_in(args["--runs"]);
  if (!runs_in) throw std::runtime_error(args["--runs"] + ": cannot be read");
  struct Timed {
    std::vector<double> wall, cpu;
  };
  std::map<std::pair<std::string, std::string>, Timed> runs;  // (what, cores) -> seconds
  std::string what, cores;
  double wall, cpu;
  while (runs_in >> what >> cores >> wall >> cpu) {
    runs[{what, cores}].wall.push_back(wall);
    runs[{what, cores}].cpu.push_back(cpu);
  }
  const Result* decode = find(stages, "BM_DecodeSequence/tv1");
  const int decoded_frames = decode && decode->counters.count("frames") ? static_cast<int>(decode->counters.at("frames")) : 0;
  out << "## Whole `slamcmp run` against decoding the same files (tv1, all " << decoded_frames << " frames)\n\n"
      << "Each run is a whole process (start, the decode-ahead threads, tracking, outputs, metrics), timed "
         "against `decode_only`, a process that only reads the same files one after the other as `run` "
         "does, in the same repetitions on the same cores; medians. The target is judged on all cores: "
         "the frames decode ahead on other threads while the tracker works. On one core a run cannot "
         "come near it (its time is decoding plus tracking); those rows show the cost.";
  if (decode)
    out << " For reference, `BM_DecodeSequence` (the same decoding inside a process already started, one "
           "core): "
        << fixed(toMs(*decode) / 1e3, 3) << " s.";
  out << "\n\n| run | cores | wall s | CPU s | decode_only wall s | run / decode_only | target |\n"
         "|---|---|---|---|---|---|---|\n";
  for (const auto& [key, t] : runs) {
    if (key.first == "decode_only") continue;
    const auto baseline = runs.find({"decode_only", key.second});
    const double decode_s =
        baseline == runs.end() || key.first == "process_start" ? NAN : median(baseline->second.wall);
    out << "| " << key.first << " | " << key.second << " | " << fixed(median(t.wall), 3) << " | "
        << fixed(median(t.cpu), 3) << " | " << (std::isnan(decode_s) ? "-" : fixed(decode_s, 3)) << " | ";
    if (key.first == "process_start") {
      out << " | (`slamcmp --help`: loading OpenCV's libraries, included in every run) |\n";
      continue;
    }
    const double ratio = median(t.wall) / decode_s;  // NaN without a baseline: "missed"
    out << fixed(ratio, 2) << " | ";
    const auto target = targets.find(key.first);
    if (key.second == "1")
      out << "(one core) |\n";
    else if (target == targets.end() || std::isnan(target->second.run_over_decode))
      out << "- |\n";
    else
      out << fixed(target->second.run_over_decode, 1) << "x: "
          << (ratio <= target->second.run_over_decode ? "met" : "missed") << " |\n";
  }

  out << "\n## CSLAM stages (bench_stages)\n\n"
         "tv1: the rendered preset (640x480 PNG); board_leaves: frames with no board corner in view; "
         "vamr: the first 60 frames of ../shared/datasets/vamr_checkerboard (752x480 JPEG). Counters "
         "are per iteration (found: board found; points: features in; kept, inliers: out).\n\n";
  stageTable(out, stages);
  out << "\n## MonoSLAM EKF stages (bench_monoslam), N map features\n\n";
  stageTable(out, monoslam);

  std::ofstream file(args["--out"]);
  file << out.str();
  if (!file) throw std::runtime_error(args["--out"] + ": cannot be written");
  std::cout << out.str();
  return 0;
}

}  // namespace
}  // namespace slamcmp

int main(int argc, char** argv) {
  try {
    return slamcmp::run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "bench_report: " << e.what() << "\n";
    return 1;
  }
}
