#pragma once
// scene.yaml: the synthetic scene's true surfaces in the world frame, for scoring maps against
// them. OpenCV FileStorage; `surfaces` is a list of rectangles {name, origin, edge_u, edge_v,
// normal} (a point is origin + a edge_u + b edge_v, a and b in [0, 1]; normal towards the side a
// camera sees), `board` the chessboard's printed face (its margin included) on the wall z = 0.
#include <string>
#include <vector>

#include "datasets/scene.h"

namespace slamcmp {

struct SceneSurface {
  std::string name;
  Vec3 origin, edge_u, edge_v, normal;  // world, metres
};

struct SceneGeometry {
  SceneSurface board;
  std::vector<SceneSurface> surfaces;
};

void writeSceneYaml(const std::string& path, const Scene& scene);
// Throws InputError naming the file and field for anything missing or malformed.
SceneGeometry readSceneYaml(const std::string& path);

}  // namespace slamcmp
