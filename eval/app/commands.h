#pragma once
// The slamcmp subcommands (SPEC section 4). Each registers its options and its callback on the app;
// one file per subcommand (cmd_<name>.cc).
#include <CLI/CLI.hpp>

namespace slamcmp {

void addSynthCommand(CLI::App& app);
void addRunCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);
void addReproduceCommand(CLI::App& app);
void addEvalCommand(CLI::App& app);
void addCalibrateCommand(CLI::App& app);

}  // namespace slamcmp
