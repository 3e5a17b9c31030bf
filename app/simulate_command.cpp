// `slamprep simulate`: run the simulator for one world and scenario and write a dataset directory.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <numbers>
#include <sstream>

#include "slamprep/app/choices.hpp"
#include "slamprep/app/command_progress.hpp"
#include "slamprep/app/commands.hpp"
#include "slamprep/app/common_flags.hpp"
#include "slamprep/app/outputs.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/input_file.hpp"
#include "slamprep/core/json_input.hpp"
#include "slamprep/core/paths.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/sim/drive/scenario.hpp"
#include "slamprep/sim/drive/simulator.hpp"

namespace slamprep::app {
namespace {

struct SimulateFlags : CommonFlags {
  std::string world;
  std::string scenario;
  std::string config_file;
  std::string out;
  std::string mode;
  double duration_s = 0.0;
  std::uint64_t seed = 0;
  std::vector<std::string> overrides;
};

/// Every configuration key with its default, for --help.
std::string keysHelp() {
  std::ostringstream out;
  out << "Configuration keys for --set KEY=VALUE (defaults shown; docs/simulate.md explains "
         "them):\n";
  const nlohmann::json flat = sim::toJson(sim::SimConfig{}, true).flatten();
  for (const std::string& key : sim::configKeys()) {
    std::string pointer = "/" + key;
    for (char& ch : pointer) {
      if (ch == '.') ch = '/';
    }
    out << "  " << key << " = " << flat.at(pointer).dump() << "\n";
  }
  out << "Example: slamprep simulate --scenario worlds/scenarios/figure_eight.yaml --seed 3 "
         "--set lidar.rate_hz=5 --set nominal.wheel_base_error=0.02 --out out/fig8\n";
  return out.str();
}

/// A configuration JSON file: either the configuration object itself or a dataset.json, whose
/// "config" field holds the configuration a dataset was simulated with.
sim::SimConfig readConfigFile(const std::string& file) {
  nlohmann::json json =
      parseJsonInput(readInputFile(file, "configuration file", kMaxConfigFileBytes), file);
  if (json.is_object() && json.contains("config") && json.contains("format_version")) {
    json = json["config"];
    // Keys the dataset adds beside the simulator's configuration (docs/dataset.md).
    for (const char* key : {"encoders_from", "odometry_heading"}) json.erase(key);
  }
  return sim::configFromJson(json, file);
}

void printSummary(const sim::SimSummary& s, double wall_s, const std::string& out) {
  const double rtf = wall_s > 0.0 ? s.duration_s / wall_s : 0.0;
  const double deg = 180.0 / std::numbers::pi;
  std::printf("simulated %.2f s (%s, %zu physics steps) in %.2f s wall: %.0fx real time\n",
              s.duration_s, std::string(nameOf(sim::kSimModeNames, s.mode)).c_str(),
              s.physics_steps, wall_s, rtf);
  std::printf("scans %zu, beams %zu (%.1f %% returns)\n", s.scans, s.beams,
              s.beams > 0 ? 100.0 * s.returns / s.beams : 0.0);
  std::printf("distance driven %.2f m, turned %.1f deg\n", s.distance_m, s.rotation_rad * deg);
  std::printf("odometry drift at the end (max along the run):\n");
  std::printf("  nominal geometry  %.4f m  %+.3f deg  (max %.4f m)\n",
              s.drift_nominal.final_position_error_m, s.drift_nominal.final_error.yaw * deg,
              s.drift_nominal.max_position_error_m);
  std::printf("  true geometry     %.4f m  %+.3f deg  (max %.4f m)  slip + quantisation\n",
              s.drift_true.final_position_error_m, s.drift_true.final_error.yaw * deg,
              s.drift_true.max_position_error_m);
  std::printf("wrote %s\n", out.c_str());
}

sim::SimConfig assembleConfig(const SimulateFlags& flags, const CLI::App& cli) {
  sim::SimConfig config;
  if (!flags.config_file.empty()) config = readConfigFile(flags.config_file);
  if (cli.count("--world")) config.world = flags.world;
  if (cli.count("--scenario")) config.scenario = flags.scenario;
  if (cli.count("--duration")) config.duration_s = flags.duration_s;
  if (cli.count("--seed")) config.seed = flags.seed;
  if (cli.count("--mode")) sim::applyOverride(config, "mode=" + flags.mode);
  sim::validate(config, "command line");
  for (const std::string& assignment : flags.overrides) sim::applyOverride(config, assignment);
  return config;
}

// Every file the run reads, wherever it was named (flag, --config, --set, a scenario's include),
// so that --out can never replace one of them.
void checkOutputs(const SimulateFlags& flags, const sim::SimConfig& config) {
  OutputGuard guard(flags.force);
  guard.input(flags.config_file, "--config")
      .input(resolveDataPath(config.world), "--world")
      .input(resolveDataPath(config.scenario), "--scenario");
  for (const auto& file : sim::loadScenario(resolveDataPath(config.scenario)).files)
    guard.input(file, "--scenario (included)");
  guard.dataset(flags.out, "--out").check();  // before minutes of simulation
}

int run(const SimulateFlags& flags, const CLI::App& cli) {
  const sim::SimConfig config = assembleConfig(flags, cli);
  checkOutputs(flags, config);

  const auto start = std::chrono::steady_clock::now();  // for the summary only
  const sim::SimResult result = [&] {
    CommandProgress progress(1, "runs", "simulate", !flags.quiet);
    StageReporter stages(flags.out, 1);
    stages.begin("simulate");
    return sim::simulate(config, [&](double t_s, double duration_s) {
      if (duration_s > 0.0) stages.update(t_s / duration_s);
    });
  }();
  const double wall_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  eval::writeDataset(flags.out, result.dataset);
  printSummary(result.summary, wall_s, flags.out);
  return 0;
}

}  // namespace

Command addSimulateCommand(CLI::App& app) {
  auto flags = std::make_shared<SimulateFlags>();
  auto* cli = app.add_subcommand(
      "simulate", "Simulate a robot in Bullet; write a dataset with exact ground truth.");
  cli->add_option(
      "--world", flags->world,
      "World file (YAML, docs/worlds.md). Default: worlds/room.yaml; relative paths "
      "are looked up in the working directory, then in the data folder (docs/install.md)");
  cli->add_option("--scenario", flags->scenario,
                  "Scenario file (YAML, docs/simulate.md). Default: "
                  "worlds/scenarios/default.yaml");
  cli->add_option("--duration", flags->duration_s,
                  "Simulated seconds; 0 (default) runs the scenario's own length. Longer than "
                  "the scenario: the robot stands still at the end")
      ->check(nonNegative());
  cli->add_option("--seed", flags->seed,
                  "Seed of all sensor noise (default 1). Same seed and "
                  "configuration give byte-identical datasets")
      ->check(nonNegative());  // CLI11 would wrap -1 to 2^64 - 1
  cli->add_option("--mode", flags->mode,
                  "physics (default): Bullet rigid bodies, motors, contacts, slip. kinematic: "
                  "exact integration of the commanded wheel rates with the true geometry")
      ->check(oneOf("mode", namesOf(sim::kSimModeNames)));
  cli->add_option("--config", flags->config_file,
                  "JSON configuration applied before the other flags: a configuration object or "
                  "a dataset.json (reruns the configuration a dataset was made with)");
  cli->add_option("--set", flags->overrides,
                  "Override any configuration key, KEY=VALUE; repeatable. Unknown keys are an "
                  "error. Keys are listed below")
      ->type_name("KEY=VALUE")
      ->allow_extra_args(false);
  cli->add_option("--out", flags->out,
                  "Output dataset directory (written atomically); an existing one is refused "
                  "unless --force")
      ->required()
      ->check(outputPath());
  addForce(cli, *flags, "an existing --out dataset");
  addQuiet(cli, *flags);
  cli->footer(
      "Writes a dataset directory (docs/dataset.md) with wheel encoders, IMU, a rotating lidar\n"
      "whose scans are distorted by the motion, and exact ground truth: the true pose at every\n"
      "physics step and the undistorted point of every beam. Bullet simulates the TRUE wheel\n"
      "geometry; the odometry (and the controller) believe a NOMINAL geometry that is wrong by\n"
      "the nominal.* fractions. Before simulating, the commanded path is checked against the\n"
      "world: a scenario that would leave the free space is an error. Every option has a\n"
      "default, so `slamprep simulate --out DIR` runs the default world and scenario.\n\n" +
      keysHelp());
  return {cli, [flags, cli] { return run(*flags, *cli); }};
}

}  // namespace slamprep::app
