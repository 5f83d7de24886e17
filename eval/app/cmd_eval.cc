// slamcmp eval: trajectory error of an estimate against ground truth (SPEC section 4), and the
// error of a map (map.ply) against a synthetic scene's true surfaces (scene.yaml).
#include <cstdio>
#include <iostream>
#include <memory>
#include <optional>
#include <string>
#include <tuple>

#include "core/error.h"
#include "core/map_ply.h"
#include "core/trajectory.h"
#include "eval/app/commands.h"
#include "eval/metrics/map_metrics.h"
#include "eval/metrics/trajectory_metrics.h"

namespace slamcmp {

namespace {

struct EvalRequest {
  std::string groundtruth_path;
  std::string estimate_path;
  std::string groundtruth_times_path;  // a KITTI file's times (KITTI's times.txt)
  std::string estimate_times_path;
  std::string map_path;
  std::string scene_path;
  EvalOptions options;
  bool json = false;
};

void printRow(const char* name, const Statistics& s) {
  std::printf("%-15s %11.6f %11.6f %11.6f %11.6f %11.6f %11.6f\n", name, s.rmse, s.mean, s.median,
              s.std, s.min, s.max);
}

void printTable(const TrajectoryEvaluation& e, const EvalRequest& request) {
  // The alignment and its scale always (1 unless sim3): an unclear scale is a frequent surprise.
  std::printf("%zu pose pairs (max-diff %g s), alignment %s, scale %.6f", e.pairs.size(),
              request.options.max_diff, e.align.c_str(), e.T_gt_estimate.scale);
  if (request.options.t_offset != 0.0) std::printf(", estimate's clock offset %+g s", request.options.t_offset);
  std::printf("; RPE over %d frame%s, %zu pairs%s\n", e.rpe_delta, e.rpe_delta == 1 ? "" : "s",
              e.rpe_trans.size(), e.rpe_all_pairs ? " (all pairs)" : "");
  std::printf("%-15s %11s %11s %11s %11s %11s %11s\n", "", "rmse", "mean", "median", "std", "min",
              "max");
  printRow("ATE trans (m)", e.ate_trans_stats);
  printRow("ATE rot (deg)", e.ate_rot_deg_stats);
  printRow("RPE trans (m)", e.rpe_trans_stats);
  printRow("RPE rot (deg)", e.rpe_rot_deg_stats);
  std::printf("ATE rmse per axis (m): x %.6f  y %.6f  z %.6f\n", e.ate_axis_rmse.x(),
              e.ate_axis_rmse.y(), e.ate_axis_rmse.z());
  if (e.drift) {
    std::printf("drift (KITTI devkit, %d segments of %s over a %.3f m path):", e.drift->segments,
                e.drift->kitti_lengths ? "100..800 m" : "0.1..0.8 of the path", e.drift->path_m);
    for (const DriftAtLength& at : e.drift->lengths) std::printf(" %.3g", at.length_m);
    std::printf(" m; %.4f %% translation, %.4f deg/m rotation\n", e.drift->trans_percent, e.drift->rot_deg_per_m);
  } else {
    std::printf("drift: not measured: %s\n", e.no_drift.c_str());
  }
}

void printMapTable(const MapErrorStats& s, const EvalRequest& request) {
  std::printf("map %s: %d points against %s\n", request.map_path.c_str(), s.distance.count, request.scene_path.c_str());
  if (s.distance.count == 0) {  // only known points (an EKF's board corners): no statistics
    std::printf("no estimated point to score (%d known)\n", s.known);
    return;
  }
  std::printf("%-15s %11s %11s %11s %11s\n", "", "rmse", "median", "max", "within 1cm");
  std::printf("%-15s %11.6f %11.6f %11.6f %11.6f\n", "map error (m)", s.distance.rmse, s.distance.median,
              s.distance.max, s.within_1cm);
}

// The statistics and, in the map's point order, each point's error (metres).
nlohmann::json mapJson(const MapEvaluation& e) {
  nlohmann::json j = mapStatsToJson(e.stats);
  j["errors"] = e.errors;
  return j;
}

}  // namespace

void addEvalCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "eval",
      "trajectory error of an estimate against ground truth (ATE, RPE), as evo computes it; and/or "
      "map error against a synthetic scene (distance of each map point to the nearest true surface)");
  auto request = std::make_shared<EvalRequest>();
  auto* groundtruth_option = cmd->add_option("--groundtruth", request->groundtruth_path,
                  "ground truth trajectory: TUM, EuRoC (.csv) or KITTI")->check(nonEmptyPath());
  auto* estimate_option = cmd->add_option("--estimate", request->estimate_path, "estimated trajectory: TUM, EuRoC or KITTI")->check(nonEmptyPath());
  auto* map_option = cmd->add_option("--map", request->map_path, "map points to score (PLY, e.g. a run's map.ply)")->check(nonEmptyPath());
  auto* scene_option = cmd->add_option("--scene", request->scene_path, "the true scene (a synthetic sequence's scene.yaml)")->check(nonEmptyPath());
  auto* groundtruth_times = cmd->add_option("--groundtruth-times", request->groundtruth_times_path,
                                            "a KITTI ground truth's times, a second count a line (KITTI's times.txt): "
                                            "its poses then pair by time, also with a TUM or EuRoC estimate")
                                ->check(nonEmptyPath());
  auto* estimate_times = cmd->add_option("--estimate-times", request->estimate_times_path,
                                         "a KITTI estimate's times, as --groundtruth-times")
                             ->check(nonEmptyPath());
  groundtruth_times->needs(groundtruth_option);
  estimate_times->needs(estimate_option);
  groundtruth_option->needs(estimate_option);
  estimate_option->needs(groundtruth_option);
  map_option->needs(scene_option);
  scene_option->needs(map_option);
  cmd->add_option("--align", request->options.align,
                  "alignment of the estimate onto the ground truth: none (default); Umeyama se3 or sim3 "
                  "(also reports the scale); origin: its first matched pose onto the ground truth's (evo's "
                  "--align_origin: each pose's error relative to the first)");
  cmd->add_option("--max-diff", request->options.max_diff,
                  "largest time difference of an associated pose pair, seconds (default 0.01)");
  cmd->add_option("--t-offset", request->options.t_offset,
                  "seconds added to the estimate's timestamps before association, as evo's --t_offset "
                  "and TUM's associate.py --offset (default 0)");
  cmd->add_option("--delta", request->options.delta, "RPE step in matched poses (default 1)");
  cmd->add_flag("--all-pairs", request->options.all_pairs,
                "RPE over every pair of matched poses --delta apart, overlapping (evo_rpe --all_pairs); by "
                "default only pairs 0, delta, 2 delta, ... (evo_rpe's default)");
  cmd->add_flag("--json", request->json, "print one JSON object instead of a table");
  cmd->callback([request] {
    const bool has_map = !request->map_path.empty();
    if (request->groundtruth_path.empty() && !has_map)
      throw InputError("eval", "give --groundtruth and --estimate, or --map and --scene (or both pairs)");
    std::optional<MapEvaluation> map_evaluation;
    if (has_map) {
      const std::vector<MapPoint> map = readMapPly(request->map_path);
      if (map.empty()) throw InputError(request->map_path, "holds no map point to score");
      map_evaluation = evaluateMap(map, readSceneYaml(request->scene_path));
    }
    if (request->groundtruth_path.empty()) {
      if (request->json) {
        std::cout << nlohmann::json{{"map", mapJson(*map_evaluation)}}.dump(1) << "\n";
      } else {
        printMapTable(map_evaluation->stats, *request);
      }
      return;
    }
    request->options.check();
    const TrajectoryFormat groundtruth_format = detectTrajectoryFormat(request->groundtruth_path);
    const TrajectoryFormat estimate_format = detectTrajectoryFormat(request->estimate_path);
    for (const auto& [times, format, option] :
         {std::tuple{request->groundtruth_times_path, groundtruth_format, "--groundtruth-times"},
          {request->estimate_times_path, estimate_format, "--estimate-times"}})
      if (!times.empty() && format != TrajectoryFormat::Kitti)
        throw InputError(option, times + ": times go with a KITTI file (12 fields a line); the other formats carry their own");
    const Trajectory groundtruth =
        readTrajectory(request->groundtruth_path, groundtruth_format, request->groundtruth_times_path);
    const Trajectory estimate = readTrajectory(request->estimate_path, estimate_format, request->estimate_times_path);
    // KITTI files without their times are numbered 0, 1, 2, ..., which against a timed file pair a
    // few poses by chance. Two such files pair by index, which a file cut short or with frames
    // dropped would shift silently: evo refuses them unless both have as many poses.
    const bool groundtruth_untimed = groundtruth_format == TrajectoryFormat::Kitti && request->groundtruth_times_path.empty();
    const bool estimate_untimed = estimate_format == TrajectoryFormat::Kitti && request->estimate_times_path.empty();
    if (groundtruth_untimed != estimate_untimed) {
      throw InputError(estimate_untimed ? request->estimate_path : request->groundtruth_path,
                       "is a KITTI file (12 fields a line, no time) and " +
                           (estimate_untimed ? request->groundtruth_path : request->estimate_path) +
                           " is timed: give its times (" + (estimate_untimed ? "--estimate-times" : "--groundtruth-times") +
                           "), or pair two KITTI files by index");
    }
    if (groundtruth_untimed && estimate_untimed && groundtruth.size() != estimate.size())
      throw InputError(request->estimate_path + " against " + request->groundtruth_path,
                       "KITTI files pair their poses by index (they carry no time), so they must have as many: " +
                           std::to_string(estimate.size()) + " against " + std::to_string(groundtruth.size()));
    TrajectoryEvaluation evaluation;
    try {
      evaluation = evaluateTrajectory(groundtruth, estimate, request->options);
    } catch (const InputError& e) {  // name the two files the problem is about
      throw InputError(request->estimate_path + " against " + request->groundtruth_path, e.what());
    }
    if (!evaluation.ate_rot_warning.empty())
      std::cerr << request->estimate_path << " against " << request->groundtruth_path
                << ": warning: " << evaluation.ate_rot_warning << "\n";
    if (request->json) {
      nlohmann::json j = evaluationToJson(evaluation, request->options);
      if (map_evaluation) j["map"] = mapJson(*map_evaluation);
      std::cout << j.dump(1) << "\n";
    } else {
      printTable(evaluation, *request);
      if (map_evaluation) printMapTable(map_evaluation->stats, *request);
    }
  });
}

}  // namespace slamcmp
