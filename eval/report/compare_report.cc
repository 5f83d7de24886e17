#include "eval/report/compare_report.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "core/error.h"
#include "core/map_ply.h"
#include "core/sequence.h"
#include "eval/report/compare_figures.h"
#include "eval/report/thesis_tables.h"

namespace fs = std::filesystem;

namespace slamcmp {

namespace {


double jsonNumber(const nlohmann::json& j, std::initializer_list<const char*> path) {
  const nlohmann::json* p = &j;
  for (const char* k : path) {
    if (!p->is_object() || !p->contains(k)) return NAN;
    p = &(*p)[k];
  }
  return p->is_number() ? p->get<double>() : NAN;
}

}  // namespace

std::string fmt(double v, int precision) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << v;
  return s.str();
}

SequenceInfo readSequenceInfo(const std::string& path) {
  Sequence s = openSequence(path);
  SequenceInfo info{path, s.name, s.frames->size(), s.groundtruth, std::nullopt};
  if (const std::string scene = sceneFileOf(path); !scene.empty()) info.scene = readSceneYaml(scene);
  return info;
}

RunResult loadRun(const Method& method, const std::string& dir, const SequenceInfo& seq) {
  RunResult r;
  r.method = method;
  r.dir = dir;
  std::ifstream in(dir + "/summary.json");
  if (!in) throw InputError(dir + "/summary.json", "missing");
  r.summary = nlohmann::json::parse(in);
  r.frames = readFramesCsv(dir + "/frames.csv");
  if (r.summary.value("tracked", 0) > 0) r.trajectory = readTrajectory(dir + "/trajectory.txt", TrajectoryFormat::Tum);
  if (seq.groundtruth) r.errors = evaluateRun(*seq.groundtruth, r.trajectory, r.summary.value("alignment", "none"));
  if (seq.scene) {
    r.map = readMapPly(dir + "/map.ply");
    r.map_errors = evaluateMap(r.map, *seq.scene);
  }
  return r;
}

std::string writeCompareReport(const std::vector<SequenceInfo>& seqs, const std::vector<Method>& methods,
                               const std::vector<std::vector<RunResult>>& results, int max_frames,
                               const std::string& preamble, const std::string& out_dir) {
  std::ostringstream md;
  md << "# slamcmp comparison\n\n";
  md << preamble << "\n\n";

  // Table 3.1 and 3.2, measured here, with the thesis's numbers beside them.
  std::ofstream t31(out_dir + "/table_3_1.csv"), t32(out_dir + "/table_3_2.csv"),
      acc(out_dir + "/accuracy.csv");
  t31 << "video,frames,thesis_frames,motion\n";
  acc << "video,method,frames,tracked,first_lost_frame,ate_trans_rmse_m,ate_rot_rmse_deg,rpe_trans_rmse_m,"
         "rpe_rot_rmse_deg,ms_median,ms_p99,map_points,map_median_m,map_rmse_m,map_max_m,map_within_1cm\n";
  md << "## Table 3.1: the sequences\n\n| video | frames | thesis frames | motion |\n|---|---|---|---|\n";
  for (const auto& s : seqs) {
    const auto tv = thesisVideo(s.name);
    const int frames = max_frames >= 0 ? std::min(max_frames, s.frames) : s.frames;
    md << "| " << s.name << " | " << frames << " | " << (tv ? std::to_string(tv->frames) : "-") << " | "
       << (tv ? tv->motion : "") << " |\n";
    t31 << s.name << "," << frames << "," << (tv ? std::to_string(tv->frames) : "") << ",\""
        << (tv ? tv->motion : "") << "\"\n";
  }
  // Table 3.2: each method that stands beside a thesis column (the registry says which), then the
  // thesis's number.
  std::vector<size_t> t32_methods;
  for (size_t m = 0; m < methods.size(); ++m)
    if (!methods[m].thesis_method.empty()) t32_methods.push_back(m);
  md << "\n## Table 3.2: milliseconds per frame (median of the tracking thread's CPU time, decoding excluded: "
        "stable on a loaded machine), this machine against the thesis's\n\n| video |";
  t32 << "video";
  for (size_t m : t32_methods) {
    md << " " << methods[m].label() << " | thesis " << methods[m].thesis_method << " |";
    t32 << "," << methods[m].slug() << "_ms,thesis_" << methods[m].slug() << "_ms";
  }
  md << "\n|---|";
  for (size_t k = 0; k < t32_methods.size(); ++k) md << "---|---|";
  md << "\n";
  t32 << "\n";
  for (size_t s = 0; s < seqs.size(); ++s) {
    const auto tv = thesisVideo(seqs[s].name);
    md << "| " << seqs[s].name << " |";
    t32 << seqs[s].name;
    for (size_t m : t32_methods) {
      const RunResult& r = results[s][m];
      const double ms = r.error.empty() ? jsonNumber(r.summary, {"cpu_ms_per_frame", "median"}) : NAN;
      const double thesis = tv ? thesisMs(*tv, methods[m].thesis_method) : NAN;
      std::string c = fmt(ms, 2);
      if (std::isfinite(ms) && std::isfinite(thesis) && ms > 0) c += " (" + fmt(thesis / ms, 0) + "x faster)";
      md << " " << c << " | " << fmt(thesis) << " |";
      t32 << "," << ms << "," << thesis;
    }
    md << "\n";
    t32 << "\n";
  }

  md << "\n## Accuracy against ground truth (what the thesis could not measure)\n\n"
     << "World frame = board frame, so no alignment: ATE is the error of the pose as reported; a run started "
        "without a board (--init none) is scale-free and scored after Sim(3) alignment, marked (sim3, scale s). "
        "RPE over 1 frame.\n\n"
     << "| video | method | tracked | first lost | ATE rmse [mm] | ATE rot rmse [deg] | RPE rmse [mm] | "
        "RPE rot rmse [deg] | ms median | ms p99 |\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (size_t s = 0; s < seqs.size(); ++s)
    for (const auto& r : results[s]) {
      if (!r.error.empty()) {
        md << "| " << seqs[s].name << " | " << r.method.label() << " | failed: " << r.error << " ||||||||\n";
        acc << seqs[s].name << "," << r.method.label() << ",,,,,,,,,,,,,,\n";
        continue;
      }
      const int frames = r.summary.value("frames", 0), tracked = r.summary.value("tracked", 0);
      const auto& fl = r.summary["first_lost_frame"];
      const std::string first_lost = fl.is_number() ? std::to_string(fl.get<int>()) : "-";
      double ate = NAN, ate_rot = NAN, rpe = NAN, rpe_rot = NAN;
      if (r.errors) {
        ate = r.errors->ate_trans_rmse;
        ate_rot = r.errors->ate_rot_rmse_deg;
        rpe = r.errors->rpe_trans_rmse;
        rpe_rot = r.errors->rpe_rot_rmse_deg;
      }
      const double med = jsonNumber(r.summary, {"ms_per_frame", "median"});
      const double p99 = jsonNumber(r.summary, {"ms_per_frame", "p99"});
      const std::string aligned =
          r.errors && r.errors->align == "sim3" ? " (sim3, scale " + fmt(r.errors->T_gt_estimate.scale, 3) + ")" : "";
      md << "| " << seqs[s].name << " | " << r.method.label() << aligned << " | " << tracked << "/" << frames << " | "
         << first_lost << " | " << fmt(ate * 1e3) << " | " << fmt(ate_rot, 3) << " | " << fmt(rpe * 1e3) << " | "
         << fmt(rpe_rot, 3) << " | " << fmt(med) << " | " << fmt(p99) << " |\n";
      acc << seqs[s].name << "," << r.method.label() << "," << frames << "," << tracked << ","
          << (fl.is_number() ? first_lost : "") << "," << ate << "," << ate_rot << "," << rpe << "," << rpe_rot
          << "," << med << "," << p99 << ",";
      if (r.map_errors) {
        const MapErrorStats& m = r.map_errors->stats;
        acc << m.distance.count << "," << m.distance.median << "," << m.distance.rmse << "," << m.distance.max << ","
            << m.within_1cm << "\n";
      } else {
        acc << ",,,,\n";
      }
    }
  const auto tv_note = [&] {
    std::string note;
    for (const auto& s : seqs)
      if (const auto tv = thesisVideo(s.name); tv && tv->monoslam_lost_after)
        note += (note.empty() ? "" : ", ") + s.name + " after frame " + std::to_string(tv->monoslam_lost_after);
    return note;
  }();
  if (!tv_note.empty()) md << "\nThe thesis's MonoSLAM lost every feature on " << tv_note << ".\n";

  if (std::any_of(seqs.begin(), seqs.end(), [](const SequenceInfo& s) { return s.scene.has_value(); })) {
    md << "\n## Map accuracy against the scene's true surfaces (synthetic sequences)\n\n"
       << "Distance of each point of map.ply to the nearest surface of scene.yaml (board, walls, box faces; "
          "finite rectangles). Known points given to a back-end exactly (the EKF's four board corners) are "
          "not scored.\n\n"
       << "| video | method | points | median [mm] | rmse [mm] | max [mm] | within 1 cm |\n"
          "|---|---|---|---|---|---|---|\n";
    for (size_t s = 0; s < seqs.size(); ++s)
      for (const auto& r : results[s]) {
        if (!r.map_errors) continue;
        const MapErrorStats& m = r.map_errors->stats;
        md << "| " << seqs[s].name << " | " << r.method.label() << " | " << m.distance.count << " | "
           << fmt(m.distance.median * 1e3) << " | " << fmt(m.distance.rmse * 1e3) << " | " << fmt(m.distance.max * 1e3)
           << " | " << (m.distance.count ? fmt(100 * m.within_1cm, 0) + "%" : "-") << " |\n";
      }
  }

  md << "\n## Figures\n\n";
  for (size_t s = 0; s < seqs.size(); ++s) {
    for (const auto& path : writeCompareFigures(seqs[s], results[s], out_dir + "/figures")) {
      const std::string rel = fs::relative(path, out_dir).string();
      md << "![" << fs::path(path).stem().string() << "](" << rel << ")\n\n";
    }
  }
  const std::string report = out_dir + "/report.md";
  std::ofstream out(report);
  if (!out) throw InputError(report, "cannot be written");
  out << md.str();
  return report;
}

}  // namespace slamcmp
