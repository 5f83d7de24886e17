#include <algorithm>
#include <chrono>
#include <iostream>

#include "core/interrupt.h"
#include "datasets/camera_motion.h"
#include "datasets/synth_sequence.h"
#include "eval/app/commands.h"
#include "eval/app/compare.h"
#include "eval/app/run_sequence.h"

namespace slamcmp {

void addReproduceCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "reproduce", "render the thesis's videos tv1..tv4 and compare every back-end in every mode on "
                   "them: Tables 3.1 and 3.2, accuracy against ground truth, figures 3.7 to 3.14");
  auto out = std::make_shared<std::string>("out/reproduce");
  auto frames = std::make_shared<int>(0);
  auto jobs = std::make_shared<int>(2);
  cmd->add_option("--out", *out, "output folder")->check(nonEmptyPath())->capture_default_str();
  cmd->add_option("--frames", *frames, "render N frames of each video instead of its full length (quick look)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--jobs", *jobs, "runs at once")->capture_default_str()->check(CLI::Range(1, 64));
  cmd->callback([out, frames, jobs] {
    installInterruptHandler();
    CompareOptions options;
    options.out_dir = *out;
    options.jobs = *jobs;
    options.methods = allMethods();
    for (const char* video : {"tv1", "tv2", "tv3", "tv4"}) {
      SynthOptions synth;
      synth.preset = video;
      synth.frames = *frames;
      synth.check();
      const std::string dir = *out + "/sequences/" + video;
      const auto start = std::chrono::steady_clock::now();
      writeSyntheticSequence(synth, dir);
      std::cerr << "rendered " << dir << " (" << synth.frameCount() << " frames) in "
                << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() << " s\n";
      options.sequences.push_back(dir);
      if (interrupted()) throw Interrupted("interrupted while rendering " + dir + "; nothing ran");
    }
    std::vector<UnfinishedRun> unfinished;
    const std::string report = runCompare(options, &unfinished);
    sayCompareReport(options.out_dir, report, unfinished);
  });
}

}  // namespace slamcmp
