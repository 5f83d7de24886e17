#include <iostream>
#include <limits>

#include "core/interrupt.h"
#include "eval/app/commands.h"
#include "eval/app/run_sequence.h"
#include "eval/app/backends.h"

namespace slamcmp {

void addRunCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand("run", "run one back-end on one sequence; writes trajectory.txt, "
                                        "frames.csv, summary.json and map.ply");
  auto request = std::make_shared<RunRequest>();
  cmd->add_option("--backend", request->backend, "back-end: " + backendNames())->required();
  cmd->add_option("--sequence", request->sequence_path,
                  "sequence folder (rgb.txt), image folder, video file or EuRoC folder")->check(nonEmptyPath())
      ->required();
  cmd->add_option("--out", request->out_dir, "output folder (default runs/<sequence>-<backend>)")->check(nonEmptyPath());
  cmd->add_option("--config", request->config_path,
                  "YAML options file, one section per back-end (" + backendNames(":, ") + ":)")->check(nonEmptyPath());
  cmd->add_option("--set", request->sets,
                  "override one option: SECTION.KEY=VALUE with the YAML's path, e.g. "
                  "cslam.features.max_features=200 (repeatable)");
  auto seed = std::make_shared<int>(0);
  auto* seed_option = cmd->add_option("--seed", *seed,
                                      "every random seed of the back-end (RANSAC, new features' boxes) set to N, "
                                      "before --set (default: the back-end's own)")
                          ->check(CLI::Range(0, std::numeric_limits<int>::max()));
  cmd->add_option("--camera", request->camera_path, "camera.yaml (overrides the sequence's)")->check(nonEmptyPath());
  cmd->add_option("--target", request->target_path, "target.yaml (overrides the sequence's)")->check(nonEmptyPath());
  cmd->add_option("--max-frames", request->max_frames, "stop after N frames")
      ->check(CLI::Range(0, std::numeric_limits<int>::max()));
  cmd->add_option("--mode", request->mode, "the back-end's mode (below; default its first)");
  cmd->add_option("--init", request->init,
                  "back-ends that take it (below): board (default) | groundtruth | manual:FILE (a TUM pose) | "
                  "none (no target: scale-free start, scored after Sim(3) alignment)");
  cmd->add_option("--overlay", request->overlay_path,
                  "write every frame with what the back-end saw drawn on it: a video (.avi, .mp4, .mkv) or "
                  "a folder of PNGs, with a CSV listing the drawn positions (overlay.csv in the folder, <video>.csv beside a video)")->check(nonEmptyPath());
  cmd->add_option("--threads", request->opencv_threads,
                  "OpenCV's threads for the back-end; with 1 (the default) its work stays on the tracking thread, "
                  "whose CPU time is frames.csv's cpu_ms; with more, its workers' time is not in cpu_ms")
      ->capture_default_str();  // checked by runSequence, which compare's and the fuzzer's runs also call
  cmd->add_flag("--show", request->show, "show the drawn frames in a live window (q or Esc stops the run)");
  cmd->footer(backendsHelp());
  cmd->callback([request, seed, seed_option] {
    installInterruptHandler();
    if (seed_option->count() > 0) request->seed = *seed;
    const nlohmann::json summary = runSequence(*request);
    std::cout << summary["backend"].get<std::string>() << ": " << summary["tracked"] << "/"
              << summary["frames"] << kRunResultMark;
    if (summary["ms_per_frame"]["median"].is_number())  // null when interrupted before a frame was timed
      std::cout << ", median " << summary["ms_per_frame"]["median"].get<double>() << " ms/frame";
    if (summary.contains("ate")) std::cout << ", ATE rmse " << summary["ate"]["trans"]["rmse"] << " m";
    if (summary.contains("scale")) std::cout << " after Sim(3) alignment, scale " << summary["scale"];
    std::cout << "\n";
    // Not a finished run, though its outputs are whole for the frames done (q in --show is the
    // user's own end of the run: exit 0).
    if (interrupted())
      throw Interrupted("interrupted after " + summary["frames"].dump() + " frames; the outputs cover those and "
                        "summary.json says \"interrupted\": true");
  });
}

}  // namespace slamcmp
