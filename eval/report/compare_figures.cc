#include "eval/report/compare_figures.h"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <optional>
#include <sstream>

#include "eval/metrics/associate.h"
#include "eval/metrics/scene_distance.h"
#include "eval/metrics/trajectory_metrics.h"
#include "eval/report/plot.h"

namespace slamcmp {

namespace {

// Pose of each frame (by index) or nothing: the trajectory associated with the frames'
// timestamps as the tables associate it with the ground truth (associateByTime, 10 ms).
std::vector<std::optional<SE3>> posesByFrame(const std::vector<FrameRow>& frames, const Trajectory& traj) {
  std::vector<std::optional<SE3>> out(frames.size());
  if (frames.empty() || traj.empty()) return out;
  Trajectory stamps;
  for (const FrameRow& f : frames) stamps.push_back({f.timestamp, SE3()});
  const PosePairs pairs = associateByTime(stamps, traj, EvalOptions{}.max_diff);
  for (size_t k = 0; k < pairs.size(); ++k) out[pairs.groundtruth[k]] = traj[pairs.estimate[k]].T_world_camera;
  return out;
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
    if (!r.finished() || !r.map_errors) continue;
    for (int v = 0; v < 2; ++v) {
      const int a = views[v].first, b = views[v].second;
      PlotPanel p;
      p.title = r.method.label() + ": " + names[v] + ", " + std::to_string(r.map_errors->stats.distance.count) +
                " points, median " + fmt(r.map_errors->stats.distance.median * 1e3) + " mm";
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

}  // namespace

std::vector<std::string> writeCompareFigures(const SequenceInfo& seq, const std::vector<RunResult>& runs,
                                      const std::string& fig_dir) {
  std::vector<std::string> written;
  // Frame axis from the first run that has frames; ground truth associated by timestamp.
  const RunResult* ref = nullptr;
  for (const auto& r : runs)
    if (r.finished() && !r.frames.empty()) {
      ref = &r;
      break;
    }
  if (!ref) return written;
  std::vector<std::optional<SE3>> gt_poses;
  if (seq.groundtruth) gt_poses = posesByFrame(ref->frames, *seq.groundtruth);
  // A scale-free run (--init none) drawn in the board's frame through the Sim(3) it was scored with.
  std::vector<std::vector<std::optional<SE3>>> poses;
  bool any_aligned = false;
  for (const auto& r : runs) {
    std::vector<std::optional<SE3>> ps = r.finished() ? posesByFrame(r.frames, r.trajectory)
                                                         : std::vector<std::optional<SE3>>();
    if (r.errors && r.errors->align == "sim3") {
      any_aligned = true;
      const Similarity3& S = r.errors->T_gt_estimate;
      for (auto& p : ps)
        if (p) p = SE3(S.R * p->R(), S * p->t());
    }
    poses.push_back(std::move(ps));
  }
  const std::string alignment = any_aligned ? " (scale-free runs after their Sim(3) alignment)" : "";

  auto addAll = [&](PlotPanel& panel, auto f) {
    if (seq.groundtruth) {
      PlotSeries g = frameSeries("ground truth", "#888888", gt_poses, ref->frames, f);
      g.width = 3;
      panel.series.push_back(g);
    }
    for (size_t k = 0; k < runs.size(); ++k)
      if (runs[k].finished())
        panel.series.push_back(frameSeries(runs[k].method.label(), runs[k].method.colour, poses[k],
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
    fig.title = seq.name + ": camera trajectory in the board frame" + alignment;
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
        if (runs[k].finished()) addXY(runs[k].method.label(), runs[k].method.colour, 1.5, poses[k]);
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
    fig.title = seq.name + ": " + title + alignment;
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
    fig.title = seq.name + ": error against ground truth" + (any_aligned ? alignment : " (no alignment)");
    PlotPanel pt{"position error", "frame", "error [m]", {}, false, true};
    PlotPanel pr{"orientation error", "frame", "error [deg]", {}, false, true};
    for (size_t k = 0; k < runs.size(); ++k) {
      if (!runs[k].finished()) continue;
      const std::string label = runs[k].method.label(), colour = runs[k].method.colour;
      const auto gt = posesByFrame(runs[k].frames, *seq.groundtruth);
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
    // CPU time, as Table 3.2: the wall time moves with the machine's load.
    fig.title = seq.name + ": CPU time per frame (the tracking thread's, decoding excluded, one core)";
    PlotPanel p{"", "frame", "CPU ms per frame", {}, false, true};
    for (const auto& r : runs) {
      if (!r.finished()) continue;
      PlotSeries s;
      s.label = r.method.label();
      s.color = r.method.colour;
      for (const auto& f : r.frames) {
        s.x.push_back(f.frame);
        s.y.push_back(std::max(1e-3, f.cpu_ms));
      }
      p.series.push_back(s);
    }
    fig.panels = {p};
    save(fig, "timing");
  }
  return written;
}

}  // namespace slamcmp
