#include "cslam/feature_map.h"

#include <algorithm>
#include <cmath>

#include "core/error.h"

namespace slamcmp {

void FeatureMapOptions::check() const {
  if (method != "least_squares" && method != "midpoint_average")
    throw OptionError("method", "must be least_squares or midpoint_average, got '" + method + "'");
  if (!(min_parallax_deg >= 0 && min_parallax_deg < 90)) throw OptionError("min_parallax_deg", "must be in [0, 90)");
  if (!(max_ray_error_px > 0)) throw OptionError("max_ray_error_px", "must be positive");
}

FeatureMap::FeatureMap(const FeatureMapOptions& options, double focal_px)
    : options_(options), focal_px_(focal_px), min_parallax_cos_(std::cos(options.min_parallax_deg * M_PI / 180)) {}

void FeatureMap::addObservation(int id, const SE3& T_world_camera, const Vec2& xy_normalised) {
  Entry& e = entries_[id];
  const Ray ray = rayFromObservation(T_world_camera, xy_normalised);
  if (e.observations == 0) e.first_direction = ray.direction;
  e.max_parallax_cos = std::min(e.max_parallax_cos, e.first_direction.dot(ray.direction));
  ++e.observations;
  e.least_squares.add(ray);
  if (options_.method == "midpoint_average") e.midpoint_average.add(ray);
  update(e, ray);
}

void FeatureMap::update(Entry& e, const Ray& newest) const {
  e.usable = false;
  if (e.max_parallax_cos > min_parallax_cos_) return;
  e.p_world = options_.method == "midpoint_average" ? e.midpoint_average.solve() : e.least_squares.solve();
  if (!e.p_world) return;
  const double depth = (*e.p_world - newest.origin).dot(newest.direction);
  if (depth <= 0) return;
  e.usable = focal_px_ * e.least_squares.rmsDistance(*e.p_world) / depth <= options_.max_ray_error_px;
}

std::optional<Vec3> FeatureMap::position(int id) const {
  const auto it = entries_.find(id);
  if (it == entries_.end() || !it->second.usable) return std::nullopt;
  return it->second.p_world;
}

int FeatureMap::numUsable() const {
  int n = 0;
  for (const auto& [id, e] : entries_) n += e.usable;
  return n;
}

void FeatureMap::forgetIfUnusable(int id) {
  const auto it = entries_.find(id);
  if (it != entries_.end() && !it->second.usable) entries_.erase(it);
}

std::vector<MapPoint> FeatureMap::points() const {
  std::vector<MapPoint> out;
  for (const auto& [id, e] : entries_)
    if (e.usable) out.push_back({id, *e.p_world, e.observations, -1});
  std::sort(out.begin(), out.end(), [](const MapPoint& a, const MapPoint& b) { return a.id < b.id; });
  return out;
}

}  // namespace slamcmp
