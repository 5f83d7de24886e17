#pragma once
// The slamcmp subcommands (SPEC section 4). Each registers its options and its callback on the app;
// one file per subcommand (cmd_<name>.cc).
#include <CLI/CLI.hpp>

namespace slamcmp {

// A path option given as '' (an unset shell variable: --out "$DIR") is a usage error naming the
// option ("--out: is empty ..."), never the current folder or a default.
inline CLI::Validator nonEmptyPath() {
  return CLI::Validator(
      [](std::string& value) { return value.empty() ? std::string("is empty; give a path") : std::string(); }, "",
      "NONEMPTY");
}

void addSynthCommand(CLI::App& app);
void addRunCommand(CLI::App& app);
void addCompareCommand(CLI::App& app);
void addReproduceCommand(CLI::App& app);
void addEvalCommand(CLI::App& app);
void addCalibrateCommand(CLI::App& app);

}  // namespace slamcmp
