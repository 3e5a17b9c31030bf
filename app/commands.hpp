#pragma once
// The slamprep CLI: each command maps its flags onto params structs and calls into eval/sim/algo.
// The contract they share (README, "Commands"): one-line description plus a footer, paths and
// options checked first (app/outputs.hpp), named choices with app/choices.hpp, exit codes from
// app/exit_codes.hpp.

#include <CLI/CLI.hpp>
#include <functional>

namespace slamprep::app {

/// A registered subcommand and what runs when it is the one parsed; run() returns the exit code
/// (InputError -> 2 and any other exception -> 1 are main.cpp's).
struct Command {
  CLI::App* cli = nullptr;
  std::function<int()> run;
};

// One function per command, defined in <name>_command.cpp. Add new ones to main.cpp's list.
Command addBenchCommand(CLI::App& app);
Command addCalibrateCommand(CLI::App& app);
Command addDeskewCommand(CLI::App& app);
Command addExportCommand(CLI::App& app);
Command addImportCommand(CLI::App& app);
Command addMatchCommand(CLI::App& app);
Command addMergeCommand(CLI::App& app);
Command addPlotCommand(CLI::App& app);
Command addScoreCommand(CLI::App& app);
Command addSimulateCommand(CLI::App& app);
Command addTwinCommand(CLI::App& app);

}  // namespace slamprep::app
