#include <chrono>
#include <iostream>
#include <memory>

#include "core/error.h"
#include "core/format_string.h"
#include "datasets/synth_sequence.h"
#include "eval/app/commands.h"
#include "eval/app/run_sequence.h"

namespace slamcmp {

void addSynthCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "synth", "render a synthetic sequence (a chessboard in a textured room, exact ground truth) "
               "into a sequence folder: rgb/, rgb.txt, camera.yaml, target.yaml, groundtruth.txt, "
               "scene.yaml, info.yaml");
  auto options = std::make_shared<SynthOptions>();
  auto out_dir = std::make_shared<std::string>();
  std::string presets;
  for (const MotionPreset& p : motionPresets())
    presets += "\n  " + p.name + ": " + std::to_string(p.frames) + " frames" +
               (p.fps != kSyntheticFps ? " at " + formatString("%g", p.fps) + " fps" : "") + ", " + p.description;
  cmd->add_option("--preset", options->preset, "camera motion (640x480, 10 fps unless said):" + presets)->required();
  cmd->add_option("--out", *out_dir, "output folder (created; existing files are overwritten)")->check(nonEmptyPath())->required();
  cmd->add_option("--seed", options->seed, "seed of textures, jitter and noise (default 1)");
  auto* frames_option = cmd->add_option("--frames", options->frames,
                                        "number of frames, at most 100000 (default: the preset's; beyond it the "
                                        "motion repeats)");
  cmd->add_option("--noise", options->noise, "Gaussian sensor noise sigma, grey levels (default 0)");
  cmd->add_option("--blur", options->blur,
                  "motion blur: streak length at the image centre, pixels (default 0)");
  cmd->add_option("--lens-blur", options->lens_blur,
                  "optics' blur: Gaussian point spread sigma, pixels (default 0.7)");
  cmd->add_option("--illumination", options->illumination,
                  "slow brightness change, relative amplitude, e.g. 0.15 (default 0)");
  cmd->add_option("--rolling-shutter", options->rolling_shutter,
                  "seconds from reading the top row to reading the bottom row, the middle row at the frame's "
                  "time (default 0: a global shutter)");
  cmd->add_option("--supersample", options->supersample,
                  "anti-aliasing samples per pixel along each axis (default 3)");
  cmd->callback([options, out_dir, frames_option] {
    // 0 stands for the preset's length inside; given, it is a mistake, not a request for 337 frames.
    if (frames_option->count() > 0 && options->frames < 1)
      throw InputError("--frames", "must be at least 1 (leave it out for the preset's), got " +
                                       std::to_string(options->frames));
    installInterruptHandler();  // Ctrl-C or SIGTERM: the frames rendered are listed, exit 130
    const auto start = std::chrono::steady_clock::now();
    writeSyntheticSequence(*options, *out_dir);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    std::cout << "synth: " << options->frameCount() << " frames of " << options->preset << " in "
              << *out_dir << " (" << seconds << " s)\n";
  });
}

}  // namespace slamcmp
