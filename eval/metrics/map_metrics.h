#pragma once
// Map accuracy on synthetic sequences: the distance of every map point to the nearest true scene
// surface (scene.yaml), summarised as their statistics and the share within 1 cm.
#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/statistics.h"
#include "core/tracker.h"
#include "datasets/scene_yaml.h"
#include "eval/metrics/align_umeyama.h"

namespace slamcmp {

constexpr double kMapInlierDistance = 0.01;  // metres: "within 1 cm"

struct MapErrorStats {
  Statistics distance;     // metres, over the estimated points scored (count: how many)
  int known = 0;           // points given to the back-end exactly (sigma 0, e.g. EKF's board corners): not scored
  double within_1cm = NAN;  // share of the scored points within kMapInlierDistance, in [0, 1]; NaN without any
};
MapErrorStats mapErrorStats(const std::vector<double>& errors);

struct MapEvaluation {
  MapErrorStats stats;
  std::vector<double> errors;  // metres, one per map point in the map's order
  std::vector<int> nearest;    // the nearest surface of each point, an index into sceneSurfaces()
};
// Every point gets its error; the statistics leave out the known points (sigma exactly 0), which
// would score 0 by construction and flatter a small map.
MapEvaluation evaluateMap(const std::vector<MapPoint>& map, const SceneGeometry& scene);

// A run's map.ply as written, in the ground truth's frame: a scale-free run's (given its
// trajectory's Sim(3) alignment, T_gt_estimate) through that alignment, any other's as it is.
// Scored so by `run` and by compare --collect alike, which then agree to the digit.
std::vector<MapPoint> readRunMap(const std::string& ply_path, const Similarity3* T_gt_estimate);

// {points, known, rmse, median, max, within_1cm}; the statistics are null when there are no points.
nlohmann::json mapStatsToJson(const MapErrorStats& stats);

// <sequence folder>/scene.yaml when the sequence is a folder holding one, else "".
std::string sceneFileOf(const std::string& sequence_path);

}  // namespace slamcmp
