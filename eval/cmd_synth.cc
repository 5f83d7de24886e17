#include "eval/commands.h"

namespace slamcmp {

void addSynthCommand(CLI::App& app) { app.add_subcommand("synth", "render a synthetic sequence"); }

}  // namespace slamcmp
