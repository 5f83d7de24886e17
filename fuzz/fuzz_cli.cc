// libFuzzer target: argument vectors (the input's lines, one argument each) into the slamcmp
// command line (eval/app/cli.h), stopped once the arguments are parsed and checked, before any
// subcommand's callback: nothing is read, rendered or written. The exit code must be 0 or 2; an
// internal failure (1) or an escaping exception is a finding. (The callbacks are not replaced:
// they own the variables the options write into.)
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "eval/app/cli.h"
#include "fuzz/fuzz_input.h"

namespace {
struct Parsed {};  // not a std::exception: runCommandLine lets it through
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> args{"slamcmp"};
  std::string current;
  for (size_t i = 0; i < size; ++i) {
    if (data[i] == '\n') {
      args.push_back(current);
      current.clear();
    } else {
      current.push_back(static_cast<char>(data[i]));
    }
  }
  if (!current.empty()) args.push_back(current);
  std::vector<const char*> argv;
  for (const std::string& a : args) argv.push_back(a.c_str());

  CLI::App app{"slamcmp"};
  slamcmp::addCommands(app);
  app.parse_complete_callback([] { throw Parsed{}; });  // runs before the subcommands' callbacks
  std::ostringstream out, err;
  int code = 0;
  try {
    code = slamcmp::runCommandLine(app, static_cast<int>(argv.size()), argv.data(), out, err);
  } catch (const Parsed&) {
  }
  if (code != 0 && code != 2) std::abort();
  return 0;
}
