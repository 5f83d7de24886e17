#include "datasets/scene_yaml.h"

#include "core/error.h"
#include "core/yaml.h"

namespace slamcmp {

namespace {

void writeVec(cv::FileStorage& fs, const char* key, const Vec3& v) {
  fs << key << "[:" << v.x() << v.y() << v.z() << "]";
}

void writeSurface(cv::FileStorage& fs, const TexturedRect& r) {
  fs << "{" << "name" << r.name;
  writeVec(fs, "origin", r.origin);
  writeVec(fs, "edge_u", r.size_u * r.axis_u);
  writeVec(fs, "edge_v", r.size_v * r.axis_v);
  writeVec(fs, "normal", r.normal);
  fs << "}";
}

Vec3 readVec(const cv::FileNode& node, const std::string& where) {
  if (!node.isSeq() || node.size() != 3) throw InputError(where, "must be a list of 3 numbers");
  return Vec3(readDouble(node[0], where), readDouble(node[1], where), readDouble(node[2], where));
}

SceneSurface readSurface(const cv::FileNode& node, const std::string& where) {
  if (!node.isMap()) throw InputError(where, "must be a map");
  SceneSurface s;
  s.name = readString(node["name"], where + ".name");
  s.origin = readVec(node["origin"], where + ".origin");
  s.edge_u = readVec(node["edge_u"], where + ".edge_u");
  s.edge_v = readVec(node["edge_v"], where + ".edge_v");
  s.normal = readVec(node["normal"], where + ".normal");
  return s;
}

}  // namespace

void writeSceneYaml(const std::string& path, const Scene& scene) {
  cv::FileStorage fs;
  try {
    fs.open(path, cv::FileStorage::WRITE | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception&) {
  }
  if (!fs.isOpened()) throw InputError(path, "cannot be written");
  fs.writeComment("Synthetic scene, world frame = board frame (metres). A surface is the rectangle "
                  "origin + a edge_u + b edge_v, a, b in [0, 1]; normal: the side cameras see.");
  fs << "board";
  writeSurface(fs, scene.boardRect());
  fs << "surfaces" << "[";
  for (const TexturedRect& r : scene.surfaces) writeSurface(fs, r);
  fs << "]";
}

SceneGeometry readSceneYaml(const std::string& path) {
  YamlFile file(path);
  SceneGeometry g;
  if (!file.has("board")) throw InputError(path + ": board", "missing field");
  g.board = readSurface(file.node("board"), path + ": board");
  const cv::FileNode list = file.node("surfaces");
  if (!list.isSeq() || list.size() == 0) throw InputError(path + ": surfaces", "must be a non-empty list");
  int k = 0;
  for (const auto& node : list)
    g.surfaces.push_back(readSurface(node, path + ": surfaces[" + std::to_string(k++) + "]"));
  return g;
}

}  // namespace slamcmp
