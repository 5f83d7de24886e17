#include "eval/app/cli.h"

#include <exception>

#include "core/error.h"
#include "eval/app/commands.h"
#include "eval/app/compare.h"
#include "eval/app/run_sequence.h"

namespace slamcmp {

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
    err << "slamcmp: " << e.what() << " (see slamcmp --help)\n";
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
