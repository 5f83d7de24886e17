#include "eval/app/cli.h"

#include <exception>
#include <string>
#include <vector>

#include "core/error.h"
#include "core/interrupt.h"
#include "eval/app/commands.h"
#include "eval/app/compare.h"

namespace slamcmp {

namespace {

// CLI11 answers a misspelt subcommand with "A subcommand is required": name the word it did not
// take and the subcommands there are. "" when the parse failed for another reason.
std::string unknownSubcommand(const CLI::App& app) {
  const std::vector<std::string> words = app.remaining();
  if (!app.get_subcommands().empty() || words.empty() || words.front().rfind('-', 0) == 0) return "";
  std::string known;
  for (const CLI::App* command : app.get_subcommands([](const CLI::App*) { return true; }))
    known += (known.empty() ? "" : ", ") + command->get_name();
  return "unknown subcommand '" + words.front() + "' (known: " + known + ")";
}

}  // namespace

void addCommands(CLI::App& app) {
  app.require_subcommand(1);
  app.set_version_flag("--version", "slamcmp 0.1");
  addSynthCommand(app);
  addRunCommand(app);
  addCompareCommand(app);
  addReproduceCommand(app);
  addEvalCommand(app);
  addCalibrateCommand(app);
}

int runCommandLine(CLI::App& app, int argc, const char* const* argv, std::ostream& out, std::ostream& err) {
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e, out, err);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e, out, err);
  } catch (const CLI::ParseError& e) {
    const std::string unknown = unknownSubcommand(app);
    err << "slamcmp: " << (unknown.empty() ? e.what() : unknown) << " (see slamcmp --help)\n";
    return 2;
  } catch (const Interrupted& e) {
    err << "slamcmp: " << e.what() << "\n";
    return 130;  // as a shell reports a command stopped by Ctrl-C
  } catch (const InputError& e) {
    err << "slamcmp: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    err << "slamcmp: internal error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}

}  // namespace slamcmp
