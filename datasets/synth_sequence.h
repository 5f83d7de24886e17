#pragma once
// `slamcmp synth`: renders a preset into a sequence folder (SPEC section 3): rgb/NNNNNN.png,
// rgb.txt, camera.yaml, target.yaml, groundtruth.txt (exact T_world_camera), scene.yaml (the true
// surfaces) and info.yaml (the options used).
#include <optional>
#include <string>

#include "datasets/camera_motion.h"

namespace slamcmp {

struct SynthOptions {
  std::string preset = "tv1";  // a name in motionPresets()
  int seed = 1;                // textures, jitter and noise; the same seed gives the same images
  int frames = 0;              // 0: the preset's own length; more repeats its motion
  double noise = 0.0;          // Gaussian sensor noise, grey levels (sigma)
  double blur = 0.0;           // motion blur streak at the image centre, pixels
  double lens_blur = 0.7;      // Gaussian point spread of the optics, sigma in pixels
  double illumination = 0.0;   // relative amplitude of a slow change of brightness, e.g. 0.15
  double rolling_shutter = 0.0;  // seconds from the top row's read to the bottom row's (0: global shutter)
  int supersample = 3;         // anti-aliasing samples per pixel along each axis

  template <class V>
  void visit(V& v) {
    v("preset", preset, "the camera motion, a preset of `slamcmp synth --help`");
    v("seed", seed, "textures, jitter and noise; the same seed gives the same images");
    v("frames", frames, "0: the preset's own length; more repeats its motion");
    v("noise", noise, "Gaussian sensor noise, grey levels (sigma)");
    v("blur", blur, "motion blur streak at the image centre, pixels");
    v("lens_blur", lens_blur, "Gaussian point spread of the optics, sigma in pixels");
    v("illumination", illumination, "relative amplitude of a slow brightness change");
    v("rolling_shutter", rolling_shutter,
      "seconds from the top row's read to the bottom row's, the middle row at the frame's time (0: global shutter)");
    v("supersample", supersample, "anti-aliasing samples per pixel along each axis");
  }
  void check() const;  // InputError naming the option
  int frameCount() const;  // frames, or the preset's length
};

// The options a sequence folder was rendered with (its info.yaml), or nothing when it has none (not
// a synthetic sequence). Throws InputError naming the file and field for a malformed info.yaml.
std::optional<SynthOptions> readSynthInfo(const std::string& sequence_dir);

// "" when the folder is what its info.yaml renders (the camera, the board, the frames' list and
// their size), else what differs: a copy of a render resized, cut or given another target keeps
// the info.yaml, and a new render from it would not be that sequence.
std::string differenceFromItsRender(const std::string& sequence_dir, const SynthOptions& info);

// Renders the sequence into out_dir (created if needed; existing files are overwritten, and an
// earlier render's frames there removed). Shows progress on a terminal. Throws InputError if
// out_dir cannot be written.
void writeSyntheticSequence(const SynthOptions& options, const std::string& out_dir);

}  // namespace slamcmp
