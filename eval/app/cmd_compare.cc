#include <iostream>

#include "eval/app/backends.h"
#include "eval/app/commands.h"
#include "eval/app/compare.h"
#include "eval/app/run_sequence.h"

namespace slamcmp {

void addCompareCommand(CLI::App& app) {
  auto* cmd = app.add_subcommand(
      "compare", "run several back-ends on several sequences and write a report with tables and figures");
  auto sequences = std::make_shared<std::vector<std::string>>();
  auto backends = std::make_shared<std::string>(backendNames(","));
  auto options = std::make_shared<CompareOptions>();
  cmd->add_option("--sequence", *sequences, "a sequence folder (repeat for more)")->check(nonEmptyPath())->required();
  std::string every;
  for (const Method& m : allMethods()) every += (every.empty() ? "" : ",") + m.backend + ":" + (m.mode.empty() ? findBackend(m.backend).modes.front().name : m.mode);
  cmd->add_option("--backends", *backends,
                  "comma-separated back-ends, each optionally with a mode (default: each back-end's default "
                  "mode); all of them: " + every)
      ->capture_default_str();
  cmd->add_option("--out", options->out_dir, "output folder: report.md, *.csv, figures/, runs/")->check(nonEmptyPath())->required();
  cmd->add_option("--jobs", options->jobs, "runs at once")->capture_default_str()->check(CLI::Range(1, 64));
  cmd->add_option("--max-frames", options->max_frames, "stop each run after N frames")->check(CLI::NonNegativeNumber);
  cmd->callback([sequences, backends, options] {
    installInterruptHandler();
    options->sequences = *sequences;
    options->methods = parseMethods(*backends);
    std::cout << "report: " << runCompare(*options) << "\n";
  });
}

}  // namespace slamcmp
