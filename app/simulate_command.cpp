// `slamprep simulate`: placeholder until the simulator lands (issue 2).
#include <iostream>

#include "app/commands.hpp"

namespace slamprep::app {

Command addSimulateCommand(CLI::App& app) {
  auto* cli = app.add_subcommand("simulate", "Simulate a robot run and write a dataset directory.");
  return {cli, [] {
            std::cerr << "simulate: not implemented yet\n";
            return 1;
          }};
}

}  // namespace slamprep::app
