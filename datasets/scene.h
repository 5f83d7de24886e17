#pragma once
// The synthetic scene: an axis-aligned room (the chessboard on its wall z = 0), textured boxes
// standing in it, and ray casting through it from a camera pose. World frame = board frame
// (SPEC section 2): X along the board's columns, Y along its rows (down), Z into the board.
#include <array>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "core/geometry.h"
#include "core/target.h"

namespace slamcmp {

// A planar textured rectangle: origin + a * axis_u + b * axis_v for a in [0, size_u],
// b in [0, size_v].
struct TexturedRect {
  std::string name;
  Vec3 origin;            // a corner, world
  Vec3 axis_u, axis_v;    // unit edge directions, world
  double size_u = 0, size_v = 0;  // metres
  Vec3 normal;            // unit, pointing to the side a camera sees
  double shade = 1.0;     // lighting factor on the albedo
  cv::Mat albedo;         // CV_8U; texel (i, j) is centred at ((i + 0.5) texel, (j + 0.5) texel)
  double texel = 0;       // metres per texel
};

// An oriented box standing in the room; its faces are entries of Scene::surfaces.
struct SceneBox {
  Vec3 centre;        // world
  Mat3 R_world_box;   // box axes in the world
  Vec3 half_size;     // metres, along the box axes
  std::array<int, 6> face{};  // surface index of the -x, +x, -y, +y, -z, +z faces; -1: none
};

struct Scene {
  ChessboardTarget target;
  double board_margin = 0;   // white border around the outer squares, metres
  double board_black = 0, board_white = 0;  // albedo, grey levels
  Vec3 room_min, room_max;   // the room's inner walls, world
  std::array<int, 6> room_face{};  // surface index of the walls at room_min.x, room_max.x, ...
  std::vector<SceneBox> boxes;
  std::vector<TexturedRect> surfaces;

  // The board's printed face with its margin, on the wall z = 0 (no texture: drawn analytically).
  TexturedRect boardRect() const;
  int boardWall() const { return room_face[5]; }
};

struct SceneHit {
  int surface = -1;  // index into Scene::surfaces; -1: nothing hit
  double depth = 0;  // along the camera's z axis, metres
  Vec3 p_world;
};

// The scene seen from one camera pose; precomputes what every ray shares.
class SceneView {
 public:
  // `footprint` is the spacing of neighbouring samples' rays on the normalised image plane (about
  // 1 / (fx * samples per pixel)); it sets the box filter that anti-aliases the chessboard's edges
  // within one sample, so that the samples of a pixel together integrate over its area.
  SceneView(const Scene& scene, const SE3& T_world_camera, double footprint = 0.0);

  // The nearest surface along the ray (x, y, 1) of the camera frame.
  SceneHit intersect(double x, double y) const;
  // Grey level seen along the ray (albedo times shade; board edges box-filtered).
  double radiance(double x, double y) const;

 private:
  struct BoxInView {
    const SceneBox* box;
    Mat3 R_box_camera;
    Vec3 p_camera_in_box;   // camera centre, box frame
    bool cull;              // the box is entirely in front: test rays only inside [lo, hi]
    Vec2 xy_lo, xy_hi;      // bounds of its projection on the normalised image plane
  };
  double boardAlbedo(const Vec3& p_world, double width_x, double width_y) const;

  const Scene& scene_;
  SE3 T_world_camera_;
  double footprint_;
  Vec2 board_lo_, board_hi_;  // the board's printed face on its wall (x, y), world
  std::vector<BoxInView> boxes_;
};

// Bilinear albedo of a rectangle at the world point p (on its plane).
double sampleAlbedo(const TexturedRect& rect, const Vec3& p_world);

}  // namespace slamcmp
