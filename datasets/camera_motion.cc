#include "datasets/camera_motion.h"

#include <algorithm>
#include <cmath>

#include <opencv2/core.hpp>

#include "core/error.h"
#include "datasets/room_scene.h"

namespace slamcmp {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;
constexpr int kWavesPerAxis = 3;
constexpr double kJitterRotation = 0.006;     // radians, per wave
constexpr double kJitterTranslation = 0.002;  // metres, per wave

Vec3 boardCentre() {
  const ChessboardTarget t = syntheticTarget();
  return Vec3(0.5 * (t.cols - 1) * t.square_size, 0.5 * (t.rows - 1) * t.square_size, 0.0);
}

double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

// A point on the rectangle [-half_x, half_x] x [near, far] of the XZ plane (offsets from the
// board centre), `s` metres along its perimeter from (-half_x, near), corners rounded by averaging
// over +-round metres of perimeter.
Vec3 roundedRectangle(double s, double half_x, double near_z, double far_z, double round) {
  const double wx = 2 * half_x, wz = near_z - far_z, perimeter = 2 * (wx + wz);
  auto corner_path = [&](double a) {
    a -= perimeter * std::floor(a / perimeter);
    if (a < wx) return Vec3(-half_x + a, 0, near_z);
    a -= wx;
    if (a < wz) return Vec3(half_x, 0, near_z - a);
    a -= wz;
    if (a < wx) return Vec3(half_x - a, 0, far_z);
    a -= wx;
    return Vec3(-half_x, 0, far_z + a);
  };
  constexpr int kSamples = 17;
  Vec3 sum = Vec3::Zero();
  for (int k = 0; k < kSamples; ++k) sum += corner_path(s + round * (2.0 * k / (kSamples - 1) - 1.0));
  return sum / kSamples;
}

}  // namespace

CameraModel syntheticCamera(const std::string& preset) {
  CameraModel c;
  c.width = 640;
  c.height = 480;
  c.fx = c.fy = 525.0;
  c.cx = 319.5;
  c.cy = 239.5;
  c.num_distortion = 5;
  c.distortion = {-0.1, 0.02, 0.0003, -0.0002, 0.0, 0.0, 0.0, 0.0};
  if (preset == "roll_distortion") c.distortion = {-0.32, 0.11, 0.0004, -0.0003, -0.015, 0.0, 0.0, 0.0};
  return c;
}

const std::vector<MotionPreset>& motionPresets() {
  static const std::vector<MotionPreset> presets = {
      {"tv1", 337, "lateral motion along X, +-0.15 m at 0.8 m from the board"},
      {"tv2", 335, "vertical motion along Y, +-0.13 m at 0.85 m from the board"},
      {"tv3", 318, "towards and away from the board along Z, 0.55 to 1.15 m"},
      {"tv4", 402, "a rectangle in the XZ plane, 0.3 m wide, 0.65 to 1.05 m from the board"},
      {"board_leaves", 300,
       "pans 55 degrees away from the board and back: no board corner in view for about 6 s"},
      {"wall_turn", 300,
       "turns 90 degrees to the right-hand wall and moves along it, about 11 s without the board, then turns back"},
      {"board_partial", 240,
       "moves right, then up, facing the wall: up to half the board leaves the image by its left, then bottom, edge"},
      {"roll_distortion", 200,
       "rolls up to 110 degrees each way, the board always in view, through a strongly distorting lens"},
      {"handheld_rpy", 250,
       "rolls, tilts, then pans (up to 80 degrees/s) about a point 11 cm behind and below the camera, "
       "1.1 m from the board wall, as tum_fr1_rpy's hand-held Kinect",
       30.0},
  };
  return presets;
}

const MotionPreset& findMotionPreset(const std::string& name) {
  std::string known;
  for (const MotionPreset& p : motionPresets()) {
    if (p.name == name) return p;
    known += (known.empty() ? "" : ", ") + p.name;
  }
  throw InputError("--preset", "unknown preset '" + name + "' (known: " + known + ")");
}

SE3 lookAt(const Vec3& p_world, const Vec3& target_world, double roll) {
  const Vec3 z = (target_world - p_world).normalized();
  const Vec3 x = Vec3::UnitY().cross(z).normalized();
  const Vec3 y = z.cross(x);
  Mat3 R_world_camera;
  R_world_camera << x, y, z;
  return SE3(R_world_camera * rotationFromRotvec(Vec3(0, 0, roll)), p_world);
}

CameraMotion::CameraMotion(const std::string& preset, std::uint64_t seed) : preset_(preset) {
  findMotionPreset(preset);
  cv::RNG rng(seed * 0xD1B54A32D192ED03ull + 0x8CB92BA72F3D8DD7ull);
  for (int axis = 0; axis < 6; ++axis)
    for (int k = 0; k < kWavesPerAxis; ++k) {
      // A hand's tremor and sway: slow waves large, faster ones smaller.
      const double frequency = 0.15 * std::pow(10.0, rng.uniform(0.0, 1.0));  // 0.15 to 1.5 Hz
      const double scale = (axis < 3 ? kJitterRotation : kJitterTranslation) * 0.3 / frequency;
      jitter_[axis].push_back({scale * rng.uniform(0.5, 1.0), frequency, rng.uniform(0.0, kTwoPi)});
    }
}

SE3 CameraMotion::nominal(double t) const {
  const Vec3 c = boardCentre();
  if (preset_ == "tv1") {
    const double phi = kTwoPi * t / 16.85;  // two sweeps in 337 frames
    const Vec3 offset(0.15 * std::sin(phi), 0.015 * std::sin(0.5 * phi + 1.0),
                      -0.80 + 0.03 * std::sin(1.5 * phi));
    return lookAt(c + offset, c + Vec3(0.06 * std::sin(phi), 0, 0));
  }
  if (preset_ == "tv2") {
    const double phi = kTwoPi * t / 16.75;
    const Vec3 offset(0.015 * std::sin(0.5 * phi), 0.13 * std::sin(phi),
                      -0.85 + 0.03 * std::sin(1.5 * phi));
    return lookAt(c + offset, c + Vec3(0, 0.05 * std::sin(phi), 0));
  }
  if (preset_ == "tv3") {
    const double phi = kTwoPi * t / 15.9;
    const Vec3 offset(0.02 * std::sin(0.5 * phi + 0.5), 0.015 * std::sin(phi + 1.0),
                      -0.85 - 0.30 * std::sin(phi));
    return lookAt(c + offset, c);
  }
  if (preset_ == "tv4") {
    const double period = 20.1;  // two laps in 402 frames
    const double perimeter = 2 * (0.30 + 0.40);
    Vec3 offset = roundedRectangle(perimeter * t / period, 0.15, -0.65, -1.05, 0.06);
    offset.y() = 0.015 * std::sin(kTwoPi * t / 13.0);
    return lookAt(c + offset, c + Vec3(0.4 * offset.x(), 0, 0));
  }
  if (preset_ == "wall_turn") {
    // A 30 s cycle: the board 6 s, a 5 s turn of 90 degrees to the right-hand wall (x = 2 m; at
    // most 2.7 degrees a frame), 5 s along it (0.25 m to the right and back), a 5 s turn back, the
    // board 9 s.
    const double s = t - 30.0 * std::floor(t / 30.0);
    const double turned = smoothstep((s - 6.0) / 5.0) - smoothstep((s - 16.0) / 5.0);
    const double along = 0.25 * std::sin(M_PI * std::clamp((s - 8.0) / 11.0, 0.0, 1.0));
    const Vec3 p = c + Vec3(0.04 * std::sin(kTwoPi * t / 12.0) + along, 0.02 * std::sin(kTwoPi * t / 9.0),
                            -0.85 + 0.03 * std::sin(kTwoPi * t / 7.0));
    const Mat3 turn = rotationFromRotvec(Vec3(0, 0.5 * M_PI * turned, 0));
    return lookAt(p, p + turn * (c + Vec3(0.03 * std::sin(kTwoPi * t / 12.0), 0, 0) - p));
  }
  if (preset_ == "board_partial") {
    // Facing the wall square on at 0.7 m: half a 12 s cycle 0.38 m to the right, half 0.28 m up, so
    // the board leaves the image by its left, then its bottom, edge, up to half of it (and no box
    // comes between the camera and the board, as in the other presets).
    const double u = std::sin(kTwoPi * t / 12.0);
    const double right = std::max(u, 0.0) * std::max(u, 0.0), up = std::min(u, 0.0) * std::min(u, 0.0);
    const Vec3 p = c + Vec3(0.38 * right + 0.02 * std::sin(kTwoPi * t / 5.0), -0.28 * up,
                            -0.70 + 0.03 * std::sin(kTwoPi * t / 7.0));
    return lookAt(p, p + Vec3(0.04 * u, 0.0, 1.0));
  }
  if (preset_ == "handheld_rpy") {
    // An 8.4 s cycle: 2.8 s rolling (15 degrees, 0.7 Hz), 2.8 s tilting (18 degrees, 0.6 Hz), 2.8 s
    // panning (25 degrees, 0.4 Hz), each faded in and out, about a pivot the camera is held 8 cm in
    // front of and 8 cm above (tum_fr1_rpy's ground truth: 7.8 and 8.3 cm), the pivot swaying 1.5 cm.
    const double s = t - 8.4 * std::floor(t / 8.4);
    const double deg = M_PI / 180.0;
    auto phase = [s](double start, double amplitude, double frequency) {
      const double u = s - start;
      if (u <= 0 || u >= 2.8) return 0.0;
      return amplitude * std::sin(kTwoPi * frequency * u) * smoothstep(u / 0.5) * smoothstep((2.8 - u) / 0.5);
    };
    const double roll = phase(0.0, 15 * deg, 0.7), tilt = phase(2.8, 18 * deg, 0.6), pan = phase(5.6, 25 * deg, 0.4);
    const Vec3 pivot = c + Vec3(0.015 * std::sin(kTwoPi * t / 5.0), 0.015 * std::sin(kTwoPi * t / 3.7),
                                -1.19 + 0.015 * std::sin(kTwoPi * t / 4.3));
    const Mat3 R_world_camera = lookAt(pivot, c).R() * rotationFromRotvec(Vec3(0, pan, 0)) *
                                rotationFromRotvec(Vec3(tilt, 0, 0)) * rotationFromRotvec(Vec3(0, 0, roll));
    return SE3(R_world_camera, pivot + R_world_camera * Vec3(0.0, -0.08, 0.08));
  }
  if (preset_ == "roll_distortion") {
    // Roll of 110 degrees each way (26 s a cycle: at most 2.7 degrees a frame), small lateral and
    // depth motion, the board in view.
    const double phi = kTwoPi * t / 26.0;
    const Vec3 p = c + Vec3(0.06 * std::sin(0.7 * phi), 0.04 * std::sin(1.1 * phi + 0.3), -0.72 + 0.05 * std::sin(0.5 * phi));
    return lookAt(p, c, 110.0 * M_PI / 180.0 * std::sin(phi));
  }
  // board_leaves, a 30 s cycle: the board in view, a 4 s pan (and step right) away from it, 4 s
  // away, 4 s back, the board in view again.
  const double s = t - 30.0 * std::floor(t / 30.0);
  const double away = smoothstep((s - 7.0) / 4.0) - smoothstep((s - 15.0) / 4.0);
  const Vec3 p = c + Vec3(0.05 * std::sin(kTwoPi * t / 15.0) + 0.35 * away,
                          0.02 * std::sin(kTwoPi * t / 11.0), -0.9);
  const Vec3 aim = c + Vec3(0.03 * std::sin(kTwoPi * t / 15.0), 0, 0) - p;
  const Mat3 pan = rotationFromRotvec(Vec3(0, 55.0 * M_PI / 180.0 * away, 0));
  return lookAt(p, p + pan * aim);
}

SE3 CameraMotion::T_world_camera(double t) const {
  Vec3 j[2] = {Vec3::Zero(), Vec3::Zero()};
  for (int axis = 0; axis < 6; ++axis)
    for (const Wave& w : jitter_[axis])
      j[axis / 3][axis % 3] += w.amplitude * std::sin(kTwoPi * w.frequency * t + w.phase);
  return nominal(t) * SE3::fromRotvec(j[0], j[1]);
}

}  // namespace slamcmp
