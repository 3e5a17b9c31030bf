// slamprep: physics-simulator-driven evaluation harness for 2D lidar SLAM preprocessing.

#include <iostream>
#include <vector>

#include "app/commands.hpp"
#include "core/error.hpp"

int main(int argc, char** argv) {
  using namespace slamprep::app;
  CLI::App app{
      "slamprep: simulate a differential-drive robot with a rotating lidar in Bullet, then measure "
      "how well odometry calibration and lidar de-skew recover the truth."};
  app.require_subcommand(1);
  app.footer("Run `slamprep COMMAND --help` for a command's options.");

  const std::vector<Command> commands = {
      addBenchCommand(app),  addCalibrateCommand(app), addDeskewCommand(app), addExportCommand(app),
      addImportCommand(app), addMatchCommand(app),     addMergeCommand(app),  addPlotCommand(app),
      addScoreCommand(app),  addSimulateCommand(app),
  };

  CLI11_PARSE(app, argc, argv);
  for (const Command& command : commands) {
    if (!command.cli->parsed()) continue;
    try {
      return command.run();
    } catch (const slamprep::InputError& e) {
      std::cerr << "slamprep " << command.cli->get_name() << ": error: " << e.what() << "\n";
      return 2;
    } catch (const std::exception& e) {
      std::cerr << "slamprep " << command.cli->get_name() << ": internal error: " << e.what()
                << "\n";
      return 1;
    }
  }
  return 1;
}
