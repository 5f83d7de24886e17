// libFuzzer target: argument vectors (the input's lines, one argument each) into the slamcmp
// command line (eval/app/cli.h) with every subcommand's callback replaced by a no-op, so only the
// parsing and the option checks run: nothing is read, rendered or written. The exit code must be
// 0 or 2; an internal failure (1) or an escaping exception is a finding.
#include <cstdlib>
#include <sstream>
#include <string>
#include <vector>

#include "eval/app/cli.h"
#include "fuzz/fuzz_input.h"

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
  for (CLI::App* command : app.get_subcommands([](CLI::App*) { return true; })) command->callback([] {});
  std::ostringstream out, err;
  const int code = slamcmp::runCommandLine(app, static_cast<int>(argv.size()), argv.data(), out, err);
  if (code != 0 && code != 2) std::abort();
  return 0;
}
