#include "eval/compare.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <map>
#include <mutex>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>
#include <opencv2/core/utility.hpp>

#include "core/error.h"
#include "core/frames_csv.h"
#include "core/map_ply.h"
#include "core/progress.h"
#include "core/sequence.h"
#include "eval/map_metrics.h"
#include "eval/plot.h"
#include "eval/run_errors.h"
#include "eval/run_sequence.h"
#include "eval/scene_distance.h"
#include "eval/thesis_tables.h"
#include "eval/tracker_factory.h"

namespace fs = std::filesystem;

namespace slamcmp {

std::vector<Method> parseMethods(const std::string& list) {
  std::vector<Method> methods;
  const auto known = trackerNames();
  std::stringstream ss(list);
  std::string item;
  while (std::getline(ss, item, ',')) {
    if (item.empty()) continue;
    Method m;
    const auto colon = item.find(':');
    m.backend = item.substr(0, colon);
    if (colon != std::string::npos) m.mode = item.substr(colon + 1);
    if (std::find(known.begin(), known.end(), m.backend) == known.end())
      throw InputError("--backends", "unknown back-end '" + m.backend + "'");
    methods.push_back(m);
  }
  if (methods.empty()) throw InputError("--backends", "names no back-end");
  return methods;
}

namespace {

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

// Colours and line styles by method, stable across figures (the thesis: calibration red,
// two-view green, MonoSLAM black).
std::string colourFor(const Method& m) {
  if (m.backend == "cslam" && m.mode == "calibration") return "#d62728";
  if (m.backend == "cslam" && m.mode == "two_view") return "#2ca02c";
  if (m.backend == "cslam") return "#1f77b4";
  if (m.backend == "monoslam") return "#000000";
  return "#9467bd";
}

std::string fmt(double v, int precision = 2) {
  if (!std::isfinite(v)) return "-";
  std::ostringstream s;
  s << std::fixed << std::setprecision(precision) << v;
  return s.str();
}

// Pose of each frame (by index) or nothing, from the trajectory and frames.csv timestamps.
std::vector<std::optional<SE3>> posesByFrame(const std::vector<FrameRow>& frames, const Trajectory& traj,
                                             double tolerance) {
  std::vector<std::optional<SE3>> out(frames.size());
  size_t k = 0;
  for (size_t i = 0; i < frames.size(); ++i) {
    const double t = frames[i].timestamp;
    while (k < traj.size() && traj[k].timestamp < t - tolerance) ++k;
    if (k < traj.size() && std::abs(traj[k].timestamp - t) <= tolerance) out[i] = traj[k].T_world_camera;
  }
  return out;
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
  if (seq.groundtruth) r.errors = evaluateRun(*seq.groundtruth, r.trajectory);
  if (seq.scene) {
    r.map = readMapPly(dir + "/map.ply");
    r.map_errors = evaluateMap(r.map, *seq.scene);
  }
  return r;
}

void runAll(const CompareOptions& options, const std::vector<SequenceInfo>& seqs,
            std::vector<std::vector<RunResult>>* results) {
  struct Job {
    size_t seq, method;
  };
  std::vector<Job> jobs;
  long total_frames = 0;
  for (size_t s = 0; s < seqs.size(); ++s)
    for (size_t m = 0; m < options.methods.size(); ++m) {
      jobs.push_back({s, m});
      total_frames += options.max_frames >= 0 ? std::min(options.max_frames, seqs[s].frames) : seqs[s].frames;
    }
  results->assign(seqs.size(), std::vector<RunResult>(options.methods.size()));

  // Each run on one core: runs at once take the cores, and ms per frame mean one core.
  cv::setNumThreads(1);
  std::atomic<size_t> next{0};
  std::atomic<long> frames_done{0};
  std::atomic<int> workers_left{std::max(1, std::min<int>(options.jobs, static_cast<int>(jobs.size())))};
  std::mutex mutex;
  auto worker = [&] {
    for (size_t j; (j = next++) < jobs.size();) {
      const SequenceInfo& seq = seqs[jobs[j].seq];
      const Method& method = options.methods[jobs[j].method];
      RunRequest req;
      req.backend = method.backend;
      req.mode = method.mode;
      req.sequence_path = seq.path;
      req.out_dir = options.out_dir + "/runs/" + seq.name + "-" + method.slug();
      req.max_frames = options.max_frames;
      req.progress = false;
      req.on_frame = [&] { ++frames_done; };
      RunResult r;
      try {
        runSequence(req);
        r = loadRun(method, req.out_dir, seq);
      } catch (const std::exception& e) {
        r.method = method;
        r.dir = req.out_dir;
        r.error = e.what();
      }
      std::lock_guard<std::mutex> lock(mutex);
      (*results)[jobs[j].seq][jobs[j].method] = std::move(r);
    }
    --workers_left;
  };
  std::vector<std::thread> threads;
  const int n_workers = workers_left;
  for (int i = 0; i < n_workers; ++i) threads.emplace_back(worker);
  Progress progress("compare", static_cast<int>(total_frames));
  while (workers_left > 0 && !interrupted()) {
    progress.update(static_cast<int>(frames_done), std::to_string(std::min(next.load(), jobs.size())) + "/" +
                                                        std::to_string(jobs.size()) + " runs");
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  for (auto& t : threads) t.join();
  progress.finish();
  cv::setNumThreads(-1);
}

// Per-frame series of one quantity of the pose, NaN where a method has no pose.
template <class F>
PlotSeries frameSeries(const std::string& label, const std::string& colour,
                       const std::vector<std::optional<SE3>>& poses, const std::vector<FrameRow>& frames, F f) {
  PlotSeries s;
  s.label = label;
  s.color = colour;
  for (size_t i = 0; i < frames.size(); ++i) {
    s.x.push_back(frames[i].frame);
    s.y.push_back(poses[i] ? f(*poses[i]) : NAN);
  }
  return s;
}

// Each method's map from above (X-Z) and from the side (Z-Y, Y down), points coloured by their
// distance to the nearest true surface, the board and the scene's other surfaces outlined.
Figure mapFigure(const SequenceInfo& seq, const std::vector<RunResult>& runs) {
  const double colour_max_mm = 20;
  const std::vector<SceneSurface> surfaces = sceneSurfaces(*seq.scene);
  Figure fig;
  fig.title = seq.name + ": map points against the true scene (board frame)";
  fig.columns = 2;
  fig.panel_height_px = 420;
  const std::pair<int, int> views[] = {{0, 2}, {2, 1}};
  const char* names[] = {"top view (X-Z)", "side view (Z-Y, Y down)"};
  const char* axis[] = {"X [m]", "Y [m]", "Z [m]"};
  for (const RunResult& r : runs) {
    if (!r.error.empty() || !r.map_errors) continue;
    for (int v = 0; v < 2; ++v) {
      const int a = views[v].first, b = views[v].second;
      PlotPanel p;
      p.title = r.method.label() + ": " + names[v] + ", " + std::to_string(r.map_errors->stats.points) +
                " points, median " + fmt(r.map_errors->stats.median * 1e3) + " mm";
      p.xlabel = axis[a];
      p.ylabel = axis[b];
      p.equal_axes = true;
      p.reverse_y = b == 1;
      p.colour_max = colour_max_mm;
      p.colour_label = "distance to the scene [mm]";
      // Outlines: the board (it sets the view with the points) and the other surfaces near it.
      for (int board = 1; board >= 0; --board) {
        PlotSeries outline;
        outline.label = board ? "board" : "scene";
        outline.color = board ? "#555555" : "#bbbbbb";
        outline.width = 1;
        outline.fits_range = board;
        for (size_t i = board ? 0 : 1; i < (board ? 1 : surfaces.size()); ++i) {
          const SceneSurface& s = surfaces[i];
          for (const Vec3& c : {s.origin, Vec3(s.origin + s.edge_u), Vec3(s.origin + s.edge_u + s.edge_v),
                                Vec3(s.origin + s.edge_v), s.origin}) {
            outline.x.push_back(c[a]);
            outline.y.push_back(c[b]);
          }
          outline.x.push_back(NAN);
          outline.y.push_back(NAN);
        }
        p.series.push_back(outline);
      }
      PlotSeries points;
      points.label = "map points";
      points.points = true;
      for (size_t i = 0; i < r.map.size(); ++i) {
        points.x.push_back(r.map[i].p_world[a]);
        points.y.push_back(r.map[i].p_world[b]);
        points.colour_by.push_back(r.map_errors->errors[i] * 1e3);
      }
      p.series.push_back(points);
      fig.panels.push_back(p);
    }
  }
  return fig;
}

std::vector<std::string> writeFigures(const SequenceInfo& seq, const std::vector<RunResult>& runs,
                                      const std::string& fig_dir) {
  std::vector<std::string> written;
  // Frame axis from the first run that has frames; ground truth associated by timestamp.
  const RunResult* ref = nullptr;
  for (const auto& r : runs)
    if (r.error.empty() && !r.frames.empty()) ref = &r;
  if (!ref) return written;
  const double tol = 0.005;
  std::vector<std::optional<SE3>> gt_poses;
  if (seq.groundtruth) gt_poses = posesByFrame(ref->frames, *seq.groundtruth, tol);
  std::vector<std::vector<std::optional<SE3>>> poses;
  for (const auto& r : runs) poses.push_back(r.error.empty() ? posesByFrame(r.frames, r.trajectory, tol)
                                                             : std::vector<std::optional<SE3>>());

  auto addAll = [&](PlotPanel& panel, auto f) {
    if (seq.groundtruth) {
      PlotSeries g = frameSeries("ground truth", "#888888", gt_poses, ref->frames, f);
      g.width = 3;
      panel.series.push_back(g);
    }
    for (size_t k = 0; k < runs.size(); ++k)
      if (runs[k].error.empty())
        panel.series.push_back(frameSeries(runs[k].method.label(), colourFor(runs[k].method), poses[k],
                                           runs[k].frames, f));
  };
  auto save = [&](const Figure& fig, const std::string& stem) {
    const std::string path = fig_dir + "/" + seq.name + "_" + stem + ".png";
    writeFigurePng(fig, path);
    written.push_back(path);
  };

  // Trajectory seen from above (X-Z) and from the side (X-Y): thesis figures 3.7, 3.9, 3.11, 3.13.
  {
    Figure fig;
    fig.title = seq.name + ": camera trajectory in the board frame";
    fig.columns = 2;
    fig.panel_height_px = 480;
    const std::pair<int, int> views[] = {{0, 2}, {0, 1}};
    const char* names[] = {"top view (X-Z)", "side view (X-Y)"};
    const char* axis[] = {"X [m]", "Y [m]", "Z [m]"};
    for (int v = 0; v < 2; ++v) {
      PlotPanel p;
      p.title = names[v];
      p.xlabel = axis[views[v].first];
      p.ylabel = axis[views[v].second];
      p.equal_axes = true;
      auto addXY = [&](const std::string& label, const std::string& colour, double width,
                       const std::vector<std::optional<SE3>>& ps) {
        PlotSeries s;
        s.label = label;
        s.color = colour;
        s.width = width;
        for (const auto& pose : ps) {
          s.x.push_back(pose ? pose->t()[views[v].first] : NAN);
          s.y.push_back(pose ? pose->t()[views[v].second] : NAN);
        }
        p.series.push_back(s);
      };
      if (seq.groundtruth) addXY("ground truth", "#888888", 3, gt_poses);
      for (size_t k = 0; k < runs.size(); ++k)
        if (runs[k].error.empty()) addXY(runs[k].method.label(), colourFor(runs[k].method), 1.5, poses[k]);
      fig.panels.push_back(p);
    }
    save(fig, "trajectory");
  }
  if (seq.scene) {
    const Figure fig = mapFigure(seq, runs);
    if (!fig.panels.empty()) save(fig, "map");
  }
  // X, Y, Z and r_x, r_y, r_z against frame number: thesis figures 3.8, 3.10, 3.12, 3.14.
  auto threeAxes = [&](const std::string& title, const char* const names[3], const std::string& unit,
                       const std::string& stem, auto component) {
    Figure fig;
    fig.title = seq.name + ": " + title;
    for (int a = 0; a < 3; ++a) {
      PlotPanel p;
      p.title = names[a];
      p.xlabel = "frame";
      p.ylabel = std::string(names[a]) + " [" + unit + "]";
      addAll(p, [&component, a](const SE3& T) { return component(T)[a]; });
      fig.panels.push_back(p);
    }
    save(fig, stem);
  };
  const char* const position_names[] = {"X", "Y", "Z"};
  const char* const rotation_names[] = {"r_x", "r_y", "r_z"};
  threeAxes("camera position against frame", position_names, "m", "xyz", [](const SE3& T) { return T.t(); });
  threeAxes("camera rotation vector against frame", rotation_names, "deg", "rotation",
            [](const SE3& T) -> Vec3 { return T.rotvec() * (180.0 / M_PI); });
  // What the thesis could not measure: error against ground truth, and time, per frame.
  if (seq.groundtruth) {
    Figure fig;
    fig.title = seq.name + ": error against ground truth (no alignment)";
    PlotPanel pt{"position error", "frame", "error [m]", {}, false, true};
    PlotPanel pr{"orientation error", "frame", "error [deg]", {}, false, true};
    for (size_t k = 0; k < runs.size(); ++k) {
      if (!runs[k].error.empty()) continue;
      const std::string label = runs[k].method.label(), colour = colourFor(runs[k].method);
      const auto gt = posesByFrame(runs[k].frames, *seq.groundtruth, tol);
      auto err = [&](auto f) {
        PlotSeries s;
        s.label = label;
        s.color = colour;
        for (size_t i = 0; i < runs[k].frames.size(); ++i) {
          s.x.push_back(runs[k].frames[i].frame);
          s.y.push_back(poses[k][i] && gt[i] ? std::max(1e-6, f(*gt[i], *poses[k][i])) : NAN);
        }
        return s;
      };
      pt.series.push_back(err([](const SE3& g, const SE3& e) { return (g.t() - e.t()).norm(); }));
      pr.series.push_back(err([](const SE3& g, const SE3& e) {
        return rotationAngle(g.R().transpose() * e.R()) * 180.0 / M_PI;
      }));
    }
    fig.panels = {pt, pr};
    save(fig, "error");
  }
  {
    Figure fig;
    fig.title = seq.name + ": processing time per frame (decoding excluded, one core)";
    PlotPanel p{"", "frame", "ms per frame", {}, false, true};
    for (const auto& r : runs) {
      if (!r.error.empty()) continue;
      PlotSeries s;
      s.label = r.method.label();
      s.color = colourFor(r.method);
      for (const auto& f : r.frames) {
        s.x.push_back(f.frame);
        s.y.push_back(std::max(1e-3, f.ms));
      }
      p.series.push_back(s);
    }
    fig.panels = {p};
    save(fig, "timing");
  }
  return written;
}

double jsonNumber(const nlohmann::json& j, std::initializer_list<const char*> path) {
  const nlohmann::json* p = &j;
  for (const char* k : path) {
    if (!p->is_object() || !p->contains(k)) return NAN;
    p = &(*p)[k];
  }
  return p->is_number() ? p->get<double>() : NAN;
}

const RunResult* findRun(const std::vector<RunResult>& runs, const std::string& backend, const std::string& mode) {
  for (const auto& r : runs)
    if (r.error.empty() && r.method.backend == backend && r.method.mode == mode) return &r;
  return nullptr;
}

}  // namespace

std::string runCompare(const CompareOptions& options) {
  if (options.sequences.empty()) throw InputError("--sequence", "give at least one sequence");
  std::vector<SequenceInfo> seqs;
  for (const auto& path : options.sequences) {
    Sequence s = openSequence(path);
    SequenceInfo info{path, s.name, s.frames->size(), s.groundtruth, std::nullopt};
    if (const std::string scene = sceneFileOf(path); !scene.empty()) info.scene = readSceneYaml(scene);
    for (const auto& other : seqs)
      if (other.name == info.name) throw InputError(path, "two sequences are named '" + info.name + "'");
    seqs.push_back(std::move(info));
  }
  std::error_code ec;
  fs::create_directories(options.out_dir + "/figures", ec);
  if (ec) throw InputError(options.out_dir, "output folder cannot be created: " + ec.message());

  std::vector<std::vector<RunResult>> results;
  runAll(options, seqs, &results);

  std::ostringstream md;
  md << "# slamcmp comparison\n\n";
  md << "Methods: ";
  for (size_t m = 0; m < options.methods.size(); ++m) md << (m ? ", " : "") << "`" << options.methods[m].label() << "`";
  md << ". Each run on one core (" << std::max(1, options.jobs) << " runs at once on "
     << std::thread::hardware_concurrency() << " cores); ms per frame exclude image decoding.\n\n";

  // Table 3.1 and 3.2, measured here, with the thesis's numbers beside them.
  std::ofstream t31(options.out_dir + "/table_3_1.csv"), t32(options.out_dir + "/table_3_2.csv"),
      acc(options.out_dir + "/accuracy.csv");
  t31 << "video,frames,thesis_frames,motion\n";
  t32 << "video,cslam_combined_ms,thesis_cslam_two_view_ms,cslam_calibration_ms,thesis_cslam_calibration_ms,"
         "monoslam_ms,thesis_monoslam_ms\n";
  acc << "video,method,frames,tracked,first_lost_frame,ate_trans_rmse_m,ate_rot_rmse_deg,rpe_trans_rmse_m,"
         "rpe_rot_rmse_deg,ms_median,ms_p99,map_points,map_median_m,map_rmse_m,map_max_m,map_within_1cm\n";
  md << "## Table 3.1: the sequences\n\n| video | frames | thesis frames | motion |\n|---|---|---|---|\n";
  for (const auto& s : seqs) {
    const auto tv = thesisVideo(s.name);
    const int frames = options.max_frames >= 0 ? std::min(options.max_frames, s.frames) : s.frames;
    md << "| " << s.name << " | " << frames << " | " << (tv ? std::to_string(tv->frames) : "-") << " | "
       << (tv ? tv->motion : "") << " |\n";
    t31 << s.name << "," << frames << "," << (tv ? std::to_string(tv->frames) : "") << ",\""
        << (tv ? tv->motion : "") << "\"\n";
  }
  md << "\n## Table 3.2: milliseconds per frame (median), this machine against the thesis's\n\n"
     << "| video | cslam combined | thesis CSLAM with two-view | cslam calibration | thesis CSLAM without "
        "two-view | monoslam | thesis MonoSLAM |\n|---|---|---|---|---|---|---|\n";
  auto cell = [](const RunResult* r, double thesis) {
    const double ms = r ? jsonNumber(r->summary, {"ms_per_frame", "median"}) : NAN;
    std::string c = fmt(ms, 2);
    if (std::isfinite(ms) && std::isfinite(thesis) && ms > 0) c += " (" + fmt(thesis / ms, 0) + "x faster)";
    return std::make_pair(c, ms);
  };
  for (size_t s = 0; s < seqs.size(); ++s) {
    const auto tv = thesisVideo(seqs[s].name);
    const auto a = cell(findRun(results[s], "cslam", ""), tv ? tv->ms_cslam_two_view : NAN);
    const auto b = cell(findRun(results[s], "cslam", "calibration"), tv ? tv->ms_cslam_calibration : NAN);
    const auto c = cell(findRun(results[s], "monoslam", ""), tv ? tv->ms_monoslam : NAN);
    md << "| " << seqs[s].name << " | " << a.first << " | " << (tv ? fmt(tv->ms_cslam_two_view) : "-") << " | "
       << b.first << " | " << (tv ? fmt(tv->ms_cslam_calibration) : "-") << " | " << c.first << " | "
       << (tv ? fmt(tv->ms_monoslam) : "-") << " |\n";
    t32 << seqs[s].name << "," << a.second << "," << (tv ? tv->ms_cslam_two_view : NAN) << "," << b.second << ","
        << (tv ? tv->ms_cslam_calibration : NAN) << "," << c.second << "," << (tv ? tv->ms_monoslam : NAN) << "\n";
  }

  md << "\n## Accuracy against ground truth (what the thesis could not measure)\n\n"
     << "World frame = board frame, so no alignment: ATE is the error of the pose as reported. RPE over 1 frame.\n\n"
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
      md << "| " << seqs[s].name << " | " << r.method.label() << " | " << tracked << "/" << frames << " | "
         << first_lost << " | " << fmt(ate * 1e3) << " | " << fmt(ate_rot, 3) << " | " << fmt(rpe * 1e3) << " | "
         << fmt(rpe_rot, 3) << " | " << fmt(med) << " | " << fmt(p99) << " |\n";
      acc << seqs[s].name << "," << r.method.label() << "," << frames << "," << tracked << ","
          << (fl.is_number() ? first_lost : "") << "," << ate << "," << ate_rot << "," << rpe << "," << rpe_rot
          << "," << med << "," << p99 << ",";
      if (r.map_errors) {
        const MapErrorStats& m = r.map_errors->stats;
        acc << m.points << "," << m.median << "," << m.rmse << "," << m.max << "," << m.within_1cm << "\n";
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
        md << "| " << seqs[s].name << " | " << r.method.label() << " | " << m.points << " | " << fmt(m.median * 1e3)
           << " | " << fmt(m.rmse * 1e3) << " | " << fmt(m.max * 1e3) << " | "
           << (m.points ? fmt(100 * m.within_1cm, 0) + "%" : "-") << " |\n";
      }
  }

  md << "\n## Figures\n\n";
  for (size_t s = 0; s < seqs.size(); ++s) {
    for (const auto& path : writeFigures(seqs[s], results[s], options.out_dir + "/figures")) {
      const std::string rel = fs::relative(path, options.out_dir).string();
      md << "![" << fs::path(path).stem().string() << "](" << rel << ")\n\n";
    }
  }
  const std::string report = options.out_dir + "/report.md";
  std::ofstream out(report);
  if (!out) throw InputError(report, "cannot be written");
  out << md.str();
  return report;
}

}  // namespace slamcmp
