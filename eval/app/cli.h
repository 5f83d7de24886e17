#pragma once
// The slamcmp command line as a library: main() and the command-line fuzzer (fuzz/fuzz_cli.cc)
// build the same app and map its outcome to SPEC section 4's exit codes in one place.
#include <ostream>

#include <CLI/CLI.hpp>

namespace slamcmp {

// Adds every subcommand (eval/app/commands.h) to `app`, which must take exactly one.
void addCommands(CLI::App& app);

// Parses argv and runs the chosen subcommand's callback. Returns 0 when done; 2 for bad usage or
// bad input, with one line on `err`; 1 for an internal failure. Help and version go to `out`.
int runCommandLine(CLI::App& app, int argc, const char* const* argv, std::ostream& out, std::ostream& err);

}  // namespace slamcmp
