#pragma once
// The map (thesis section 3.2.2): each feature's 3D position from its rays in all the frames with
// a known pose where it was seen, by Algorithm 3.1 (average of pairwise closest points) or by
// linear least squares (the point nearest to all rays).
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "core/geometry.h"
#include "core/tracker.h"
#include "geometry/triangulation.h"

namespace slamcmp {

struct FeatureMapOptions {
  std::string method = "least_squares";  // "least_squares" or "midpoint_average" (Algorithm 3.1)
  double min_parallax_deg = 3.0;   // a point is usable once its rays span this angle
  double max_ray_error_px = 1.5;   // RMS ray distance from the point, as pixels at its depth
  template <class V>
  void visit(V& v) {
    v("method", method, "triangulation: least_squares (incremental) or midpoint_average (thesis Algorithm 3.1)");
    v("min_parallax_deg", min_parallax_deg, "a point is used once its rays span this angle, degrees");
    v("max_ray_error_px", max_ray_error_px,
      "a point whose rays miss it by more (RMS, as pixels at its depth) is not used");
  }
  void check() const;
};

class FeatureMap {
 public:
  FeatureMap(const FeatureMapOptions& options, double focal_px);

  // A feature seen at xy_normalised (undistorted) from a frame with a known pose.
  void addObservation(int id, const SE3& T_world_camera, const Vec2& xy_normalised);
  // The feature's position when it is well determined (parallax, consistent rays, in front).
  std::optional<Vec3> position(int id) const;
  int numUsable() const;
  // Forgets a feature that is no longer tracked and never became usable: it can gain no further
  // observations, and keeping it would make the map grow with every feature ever detected.
  void forgetIfUnusable(int id);
  std::vector<MapPoint> points() const;  // usable points only

 private:
  struct Entry {
    RayLeastSquares least_squares;
    RayMidpointAverage midpoint_average;  // Algorithm 3.1, fed only when it is the method
    Vec3 first_direction = Vec3::Zero();
    double max_parallax_cos = 1.0;  // smallest cosine between the first ray and any later one
    std::optional<Vec3> p_world;
    bool usable = false;
    int observations = 0;
  };
  void update(Entry& e, const Ray& newest) const;

  FeatureMapOptions options_;
  double focal_px_;
  double min_parallax_cos_;
  std::unordered_map<int, Entry> entries_;
};

}  // namespace slamcmp
