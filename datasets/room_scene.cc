#include "datasets/room_scene.h"

#include <cmath>

#include "datasets/procedural_texture.h"

namespace slamcmp {

namespace {

constexpr double kFloorY = 0.55;        // metres below the board's origin (Y points down)
constexpr double kFineTexel = 0.00125;  // metres; the board wall and the boxes, seen close up
constexpr double kCoarseTexel = 0.002;  // metres; the other walls

// Fixed lighting: a direction towards the light (above, on the camera's side) and an ambient part.
double shadeFor(const Vec3& normal) {
  const Vec3 towards_light = Vec3(-0.3, -0.6, -0.75).normalized();
  return 0.45 + 0.55 * std::max(0.0, normal.dot(towards_light));
}

int addSurface(Scene& scene, const std::string& name, const Vec3& origin, const Vec3& axis_u,
               const Vec3& axis_v, double size_u, double size_v, const Vec3& normal, double texel,
               std::uint64_t seed) {
  TexturedRect r;
  r.name = name;
  r.origin = origin;
  r.axis_u = axis_u;
  r.axis_v = axis_v;
  r.size_u = size_u;
  r.size_v = size_v;
  r.normal = normal;
  r.shade = shadeFor(normal);
  r.texel = texel;
  r.albedo = makeClutterTexture(size_u, size_v, texel, seed * 1000 + scene.surfaces.size());
  scene.surfaces.push_back(std::move(r));
  return static_cast<int>(scene.surfaces.size()) - 1;
}

void addRoom(Scene& scene, std::uint64_t seed) {
  static const char* const kNames[6] = {"wall_left",  "wall_right", "ceiling",
                                        "floor",      "wall_front", "wall_board"};
  const Vec3 extent = scene.room_max - scene.room_min;
  for (int face = 0; face < 6; ++face) {
    const int k = face / 2, ku = (k + 1) % 3, kv = (k + 2) % 3;
    const bool at_max = face % 2 == 1;
    Vec3 origin = scene.room_min;
    if (at_max) origin[k] = scene.room_max[k];
    const Vec3 normal = (at_max ? -1.0 : 1.0) * Vec3::Unit(k);
    scene.room_face[face] = addSurface(scene, kNames[face], origin, Vec3::Unit(ku), Vec3::Unit(kv),
                                       extent[ku], extent[kv], normal,
                                       face == 5 ? kFineTexel : kCoarseTexel, seed);
  }
}

// A box standing on the floor: footprint centre (x, z), sizes along its own x and z, its top at
// height top_y (world Y), turned by `yaw` about the vertical.
void addBox(Scene& scene, const std::string& name, double x, double z, double size_x, double size_z,
            double top_y, double yaw, std::uint64_t seed) {
  SceneBox box;
  const double height = kFloorY - top_y;
  box.centre = Vec3(x, kFloorY - 0.5 * height, z);
  box.R_world_box = Eigen::AngleAxisd(yaw, Vec3::UnitY()).toRotationMatrix();
  box.half_size = 0.5 * Vec3(size_x, height, size_z);
  static const char* const kFaceNames[6] = {"_left", "_right", "_top", "_bottom", "_front", "_back"};
  for (int face = 0; face < 6; ++face) {
    box.face[face] = -1;
    if (face == 3) continue;  // the bottom stands on the floor: never seen
    const int k = face / 2, ku = (k + 1) % 3, kv = (k + 2) % 3;
    const double side = face % 2 == 1 ? 1.0 : -1.0;
    Vec3 corner_box = -box.half_size;
    corner_box[k] = side * box.half_size[k];
    const Mat3& R = box.R_world_box;
    box.face[face] = addSurface(scene, name + kFaceNames[face], box.centre + R * corner_box,
                                R.col(ku), R.col(kv), 2 * box.half_size[ku], 2 * box.half_size[kv],
                                side * R.col(k), kFineTexel, seed);
  }
  scene.boxes.push_back(box);
}

}  // namespace

ChessboardTarget syntheticTarget() {
  ChessboardTarget t;
  t.cols = 9;
  t.rows = 6;
  t.square_size = 0.04;
  return t;
}

Scene buildRoomScene(std::uint64_t seed) {
  Scene scene;
  scene.target = syntheticTarget();
  scene.board_margin = 0.035;
  scene.board_black = 30;
  scene.board_white = 215;
  scene.room_min = Vec3(-1.6, -1.0, -3.0);
  scene.room_max = Vec3(2.0, kFloorY, 0.0);  // the board wall is z = 0
  addRoom(scene, seed);
  // The board with its margin spans x in [-0.075, 0.395], y in [-0.075, 0.275]. While it is in view
  // the presets' cameras stay within x in [0, 0.4] and above y = 0.27, so boxes left of x = -0.08,
  // right of x = 0.4 or with their tops below y = 0.28 never hide it.
  const double deg = M_PI / 180.0;
  addBox(scene, "box_left", -0.24, -0.26, 0.24, 0.24, -0.02, 0.0, seed);
  addBox(scene, "box_right", 0.62, -0.35, 0.20, 0.16, 0.12, 25 * deg, seed);
  addBox(scene, "box_low", 0.16, -0.14, 0.28, 0.16, 0.42, -10 * deg, seed);
  addBox(scene, "box_far_left", -0.62, -0.10, 0.26, 0.14, -0.25, 0.0, seed);
  addBox(scene, "box_far_right", 1.20, -0.80, 0.40, 0.35, -0.15, 35 * deg, seed);
  addBox(scene, "box_right_low", 0.55, -0.09, 0.18, 0.12, 0.33, -15 * deg, seed);
  return scene;
}

}  // namespace slamcmp
