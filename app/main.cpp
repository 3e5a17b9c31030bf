// slamprep: physics-simulator-driven evaluation harness for 2D lidar SLAM preprocessing.
// One contract for every command: parse (every CLI11 error is exit 2), check every path and
// option, then work; exit codes in app/exit_codes.hpp.

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <iostream>
#include <string_view>
#include <vector>

#include "app/version.hpp"
#include "slamprep/app/choices.hpp"
#include "slamprep/app/commands.hpp"
#include "slamprep/app/exit_codes.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/freed_memory.hpp"
#include "slamprep/core/partial_cleanup.hpp"

namespace {

using namespace slamprep::app;

/// One line per command: what bare `slamprep` and an unknown command print.
void printCommands(const CLI::App& app, std::ostream& out) {
  out << "usage: slamprep COMMAND [OPTIONS]   (slamprep COMMAND --help: its options)\n\n"
         "commands:\n";
  for (const CLI::App* sub : app.get_subcommands({})) {
    const std::string name = sub->get_name();
    out << "  " << name << std::string(name.size() < 11 ? 11 - name.size() : 1, ' ')
        << sub->get_description() << "\n";
  }
  out << "\nslamprep --version: version and git revision\n";
}

std::vector<std::string> commandNames(const CLI::App& app) {
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
  return names;
}

/// The options of `sub` as typed ("--method", "-j"), to suggest one for a typo.
std::vector<std::string> optionNames(const CLI::App& sub) {
  std::vector<std::string> names;
  for (const CLI::Option* option : sub.get_options()) {
    for (const std::string& name : option->get_lnames()) names.push_back("--" + name);
    for (const std::string& name : option->get_snames()) names.push_back("-" + name);
  }
  return names;
}

/// CLI11's own message, then the closest option for every unknown one; always exit 2.
int parseFailure(const CLI::App& app, const CLI::ParseError& e) {
  if (e.get_exit_code() == 0) {  // --help, --version: CLI11 prints them
    return app.exit(e);
  }
  const CLI::App* sub = app.get_subcommands().empty() ? &app : app.get_subcommands().front();
  const std::string prefix = sub == &app ? "slamprep" : "slamprep " + sub->get_name();
  std::cerr << prefix << ": error: " << e.what() << "\n";
  for (std::string arg : sub->remaining()) {
    if (!arg.starts_with("-")) continue;
    arg = arg.substr(0, arg.find('='));
    if (const auto closest = closestName(arg, optionNames(*sub)))
      std::cerr << prefix << ": unknown option '" << arg << "'; did you mean '" << *closest
                << "'?\n";
  }
  std::cerr << "Run `" << prefix << " --help` for the options.\n";
  return kExitUsage;
}

/// `slamprep calib ...`: the commands and the closest one, before CLI11 sees it.
bool unknownCommand(const CLI::App& app, int argc, char** argv) {
  if (argc < 2 || std::string_view(argv[1]).starts_with("-")) return false;
  const std::vector<std::string> names = commandNames(app);
  if (std::find(names.begin(), names.end(), argv[1]) != names.end()) return false;
  std::cerr << "slamprep: error: " << unknownChoice("command", argv[1], names) << "\n\n";
  printCommands(app, std::cerr);
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  slamprep::removePartialsOnSignal();  // Ctrl-C leaves no <out>.partial-<pid> behind
  // Past a file size limit (ulimit -f) a write fails with EFBIG and the error names the file;
  // the default SIGXFSZ would kill the process without a word.
  std::signal(SIGXFSZ, SIG_IGN);
  slamprep::keepFreedMemory();  // `bench` runs trial after trial: no fresh pages for each
  CLI::App app{
      "slamprep: simulate a differential-drive robot with a rotating lidar in Bullet, then measure "
      "how well odometry calibration and lidar de-skew recover the truth."};
  app.require_subcommand(1);
  app.set_version_flag("--version",
                       std::string("slamprep ") + kVersion + " (git " + kGitRevision + ")",
                       "Print the version and the git revision it was built from");
  app.footer(
      "Run `slamprep COMMAND --help` for a command's options. Exit codes: 0 done, 2 bad input or "
      "usage, 3 the requested work could not be done, 1 internal error.");

  const std::vector<Command> commands = {
      addBenchCommand(app),  addCalibrateCommand(app), addDeskewCommand(app), addExportCommand(app),
      addImportCommand(app), addMatchCommand(app),     addMergeCommand(app),  addPlotCommand(app),
      addScoreCommand(app),  addSimulateCommand(app),  addTwinCommand(app),
  };

  if (argc < 2) {
    printCommands(app, std::cerr);
    return kExitUsage;
  }
  if (unknownCommand(app, argc, argv)) return kExitUsage;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return parseFailure(app, e);
  }
  for (const Command& command : commands) {
    if (!command.cli->parsed()) continue;
    const std::string prefix = "slamprep " + command.cli->get_name();
    try {
      // Only for the exit-code tests: an internal error in any command, on request.
      if (std::getenv("SLAMPREP_TEST_INTERNAL_ERROR"))
        throw std::logic_error("SLAMPREP_TEST_INTERNAL_ERROR is set");
      return command.run();
    } catch (const slamprep::InputError& e) {
      std::cerr << prefix << ": error: " << e.what() << "\n";
      return kExitUsage;
    } catch (const std::exception& e) {
      std::cerr << prefix << ": internal error: " << e.what() << "\n";
      return kExitInternal;
    }
  }
  return kExitInternal;
}
