#pragma once
// The synthetic camera and the motions of the presets (SPEC section 7): tv1 along X, tv2 along Y,
// tv3 along Z, tv4 a rectangle in the XZ plane, board_leaves a pan away from the board and back,
// wall_turn a turn to another wall for about 11 s, board_partial a sweep that takes up to half the board
// out of the image, roll_distortion up to 110 degrees of roll through a strongly distorting lens,
// handheld_rpy a hand-held camera at 30 fps rolling, tilting and panning about a point behind it
// (as tum_fr1_rpy's); all with smooth handheld jitter.
#include <cstdint>
#include <string>
#include <vector>

#include "core/camera.h"
#include "core/geometry.h"

namespace slamcmp {

constexpr double kSyntheticFps = 10.0;  // frames per second of the presets but handheld_rpy

// 640x480, fx = fy = 525, mild barrel distortion (5 coefficients); the preset roll_distortion's
// lens has strong barrel distortion instead (k1 = -0.32: a corner of the image 14 % inwards).
CameraModel syntheticCamera(const std::string& preset = "");

struct MotionPreset {
  std::string name;
  int frames;               // the preset's own length
  std::string description;
  double fps = kSyntheticFps;
};
const std::vector<MotionPreset>& motionPresets();
// Throws InputError naming the known presets.
const MotionPreset& findMotionPreset(const std::string& name);

// A camera at p_world looking at target_world, its x axis horizontal (image up = world -Y), then
// turned by `roll` radians about its optical axis.
SE3 lookAt(const Vec3& p_world, const Vec3& target_world, double roll = 0.0);

// T_world_camera(t) of a preset, smooth in t and defined for every t >= 0: the pattern repeats
// (so any number of frames can be rendered); the jitter is drawn from `seed`.
class CameraMotion {
 public:
  CameraMotion(const std::string& preset, std::uint64_t seed);
  SE3 T_world_camera(double t) const;

 private:
  SE3 nominal(double t) const;
  struct Wave {
    double amplitude, frequency, phase;  // metres or radians, Hz, radians
  };
  std::string preset_;
  std::vector<Wave> jitter_[6];  // rotation vector x, y, z, translation x, y, z (camera frame)
};

}  // namespace slamcmp
