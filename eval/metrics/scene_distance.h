#pragma once
// Exact distance from a point to the synthetic scene's surfaces (scene.yaml): each surface is a
// finite rectangle (parallelogram), not the infinite plane it lies in, so a point beyond a box's
// edge is scored against that edge.
#include <limits>
#include <vector>

#include "core/geometry.h"
#include "datasets/scene_yaml.h"

namespace slamcmp {

// Distance (metres) from p_world to the parallelogram origin + a edge_u + b edge_v, a, b in [0, 1].
double distanceToSurface(const Vec3& p_world, const SceneSurface& surface);

// The board first, then the scene's other surfaces: the indices NearestSurface refers to.
std::vector<SceneSurface> sceneSurfaces(const SceneGeometry& scene);

struct NearestSurface {
  int index = -1;  // into the list searched; -1 if it was empty
  double distance = std::numeric_limits<double>::infinity();  // metres
};
NearestSurface nearestSurface(const Vec3& p_world, const std::vector<SceneSurface>& surfaces);

}  // namespace slamcmp
