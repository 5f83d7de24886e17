#include "eval/metrics/map_metrics.h"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "core/map_ply.h"
#include "eval/metrics/scene_distance.h"

namespace slamcmp {

MapErrorStats mapErrorStats(const std::vector<double>& errors) {
  MapErrorStats s;
  s.distance = computeStatistics(errors);
  if (errors.empty()) return s;
  const auto within = std::count_if(errors.begin(), errors.end(), [](double e) { return e <= kMapInlierDistance; });
  s.within_1cm = static_cast<double>(within) / static_cast<double>(errors.size());
  return s;
}

MapEvaluation evaluateMap(const std::vector<MapPoint>& map, const SceneGeometry& scene) {
  const std::vector<SceneSurface> surfaces = sceneSurfaces(scene);
  MapEvaluation e;
  std::vector<double> estimated;
  for (const MapPoint& p : map) {
    const NearestSurface nearest = nearestSurface(p.p_world, surfaces);
    e.errors.push_back(nearest.distance);
    e.nearest.push_back(nearest.index);
    if (p.sigma != 0) estimated.push_back(nearest.distance);
  }
  e.stats = mapErrorStats(estimated);
  e.stats.known = static_cast<int>(map.size() - estimated.size());
  return e;
}

std::vector<MapPoint> readRunMap(const std::string& ply_path, const Similarity3* T_gt_estimate) {
  std::vector<MapPoint> map = readMapPly(ply_path);
  if (T_gt_estimate)
    for (MapPoint& p : map) p.p_world = *T_gt_estimate * p.p_world;
  return map;
}

nlohmann::json mapStatsToJson(const MapErrorStats& s) {
  auto number = [](double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); };
  return {{"points", s.distance.count},
          {"known", s.known},
          {"rmse", number(s.distance.rmse)},
          {"median", number(s.distance.median)},
          {"max", number(s.distance.max)},
          {"within_1cm", number(s.within_1cm)}};
}

std::string sceneFileOf(const std::string& sequence_path) {
  std::error_code ec;
  const std::filesystem::path scene = std::filesystem::path(sequence_path) / "scene.yaml";
  return std::filesystem::is_directory(sequence_path, ec) && std::filesystem::exists(scene, ec) ? scene.string()
                                                                                                 : std::string();
}

}  // namespace slamcmp
