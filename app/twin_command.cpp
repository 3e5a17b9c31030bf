// `slamprep twin DATASET --out DIR`: a simulation that reproduces a recording (world, drive,
// lidar, odometry fitted to it), and `slamprep twin --compare REAL TWIN`: the same statistics
// measured on both (docs/twin.md).
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "slamprep/algo/calibration/calibration_json.hpp"
#include "slamprep/app/command_progress.hpp"
#include "slamprep/app/commands.hpp"
#include "slamprep/app/common_flags.hpp"
#include "slamprep/app/outputs.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/bench/twin.hpp"
#include "slamprep/eval/bench/twin_compare.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/sim/drive/scenario.hpp"
#include "slamprep/sim/drive/simulator.hpp"
#include "slamprep/sim/physics/world.hpp"

namespace slamprep::app {
namespace {

namespace fs = std::filesystem;

struct TwinFlags : CommonFlags {
  std::string dataset;
  std::string out;
  std::string calibration;
  std::vector<std::string> compare;
  std::string plot;
  eval::TwinParams params;
  bool no_calibrate = false;
};

/// A folder `twin` wrote: it holds twin.json (or is empty).
bool isTwinFolder(const fs::path& dir) {
  return fs::is_directory(dir) && (fs::is_empty(dir) || fs::exists(dir / "twin.json"));
}

/// Simulates the fitted twin and writes DIR's files into `partial` (published as `out`).
void writeTwin(eval::TwinFit& fit, const TwinFlags& flags, const fs::path& partial,
               nlohmann::ordered_json& json) {
  writeFileAtomic(partial / "world.yaml", fit.world_yaml);
  writeFileAtomic(partial / "scenario.yaml", fit.scenario_yaml);
  if (!fit.transients_csv.empty()) writeFileAtomic(partial / "transients.csv", fit.transients_csv);
  // Simulated from the files as written (rounded), so their --set list gives the same bytes.
  fit.world = sim::loadWorld(partial / "world.yaml");
  sim::SimConfig& config = fit.config;
  config.world = (fs::path(flags.out) / "world.yaml").string();
  config.scenario = (fs::path(flags.out) / "scenario.yaml").string();
  const sim::Scenario scenario = sim::parseScenario(fit.scenario_yaml, config.scenario);
  const auto begin = std::chrono::steady_clock::now();
  const sim::SimResult r = eval::simulateTwin(fit, scenario);
  json = fit.json;
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  fs::create_directories(partial / "dataset");
  eval::writeDatasetFiles(partial / "dataset", r.dataset, fs::path(flags.out) / "dataset");
  json["simulate"] = {{"command", "slamprep simulate --world " + config.world + " --scenario " +
                                      config.scenario + " --set ... (sets) --out DIR"},
                      {"scans", r.summary.scans},
                      {"distance_m", r.summary.distance_m},
                      {"true_geometry_drift_max_m", r.summary.drift_true.max_position_error_m},
                      {"seconds", wall}};
  writeFileAtomic(partial / "twin.json", json.dump(2) + "\n");
}

int runTwin(TwinFlags flags) {
  checkInputDataset(flags.dataset, "DATASET");
  if (!flags.calibration.empty()) checkInputFile(flags.calibration, "--calibration");
  OutputGuard guard(flags.force);
  guard.input(flags.dataset, "DATASET").input(flags.calibration, "--calibration");
  guard.directory(flags.out, "--out", isTwinFolder, "a twin folder (with twin.json)");
  guard.check();
  if (!flags.calibration.empty()) {
    const algo::CalibrationFile cal = algo::readCalibrationJson(flags.calibration);
    cal.requireBest();
    flags.params.true_geometry = cal.best()->result.geometry;
  }
  flags.params.calibrate = !flags.no_calibrate;
  const auto begin = std::chrono::steady_clock::now();
  const Dataset real = eval::readDataset(flags.dataset);
  eval::TwinFit fit = [&] {
    CommandProgress progress(1, "runs", "twin", !flags.quiet);
    return eval::fitTwin(real, flags.dataset, flags.params);
  }();
  nlohmann::ordered_json json;
  eval::publishDirectoryAtomically(
      flags.out, [&](const fs::path& partial) { writeTwin(fit, flags, partial, json); },
      isTwinFolder);
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  std::printf("%s", eval::twinText(json).c_str());
  std::printf("twin of %s in %.1f s: wrote %s/{world.yaml, scenario.yaml, twin.json, dataset/}\n",
              flags.dataset.c_str(), seconds, flags.out.c_str());
  return 0;
}

int runCompare(const TwinFlags& flags) {
  const std::string& real = flags.compare[0];
  std::string twin = flags.compare[1];
  if (fs::exists(fs::path(twin) / "twin.json")) twin = (fs::path(twin) / "dataset").string();
  checkInputDataset(real, "--compare REAL");
  checkInputDataset(twin, "--compare TWIN");
  OutputGuard guard(flags.force);
  guard.input(real, "--compare REAL").input(twin, "--compare TWIN");
  if (!flags.json_out.empty()) guard.file(flags.json_out, "--json");
  if (!flags.plot.empty()) guard.file(flags.plot, "--plot");
  guard.check();
  const eval::TwinComparison c = [&] {
    CommandProgress progress(1, "runs", "twin", !flags.quiet);
    return eval::compareTwin(real, twin);
  }();
  std::printf("%s", eval::comparisonText(c).c_str());
  if (!flags.json_out.empty())
    writeFileAtomic(flags.json_out, eval::comparisonJson(c).dump(2) + "\n");
  if (!flags.plot.empty()) eval::plotComparison(c, flags.plot);
  for (const auto& [file, what] : {std::pair{flags.json_out, "comparison"}, {flags.plot, "plot"}})
    if (!file.empty()) std::printf("wrote %s %s\n", what, file.c_str());
  return 0;
}

int run(TwinFlags& flags) {
  if (!flags.compare.empty()) {
    if (!flags.dataset.empty() || !flags.out.empty())
      throw InputError("--compare", "takes REAL and TWIN only: no DATASET and no --out");
    return runCompare(flags);
  }
  if (flags.dataset.empty()) throw InputError("DATASET", "give a dataset (or --compare REAL TWIN)");
  if (flags.out.empty()) throw InputError("--out", "required: the folder the twin is written to");
  if (!flags.json_out.empty() || !flags.plot.empty())
    throw InputError("--json", "--json and --plot go with --compare");
  return runTwin(flags);
}

}  // namespace

Command addTwinCommand(CLI::App& app) {
  auto flags = std::make_shared<TwinFlags>();
  auto* cli = app.add_subcommand(
      "twin", "A simulation that reproduces a recording, and its comparison with the recording.");
  cli->footer(
      "slamprep twin DATASET --out DIR: matches the scans to a map (slamprep match), makes the\n"
      "map's walls a world, the matched trajectory (smoothed of the matches' jitter, carried to\n"
      "the wheels by the lidar mount the calibration finds where it departs from the told one)\n"
      "wheel-rate commands, fits the lidar (rate, beams, layout, range noise, a range bias by\n"
      "beam, no-returns, usable range, mount) and the odometry (geometry, rate, gaps, clock lag,\n"
      "stamp jitter, slip of each wheel, in turns and of both wheels, gyro), replays the\n"
      "returns no other moment of the recording supports (people, things moved) where and when\n"
      "they were seen, and writes DIR/world.yaml, DIR/scenario.yaml, DIR/transients.csv,\n"
      "DIR/twin.json (every value with how it was measured,\n"
      "and the --set list) and DIR/dataset/ (simulated, told the recording's mount). The drive\n"
      "is simulated with physics, the commands corrected in closed loop toward their kinematic\n"
      "replay, or kinematically when even so the physics' robot leaves it by more than 0.3 m\n"
      "(twin.json drive.mode says which); the range noise is tuned to the recording's\n"
      "scan-to-map residual, its correlation along the scan and the share of it fixed in the\n"
      "world to the recording's.\n"
      "slamprep twin --compare REAL TWIN [--json FILE] [--plot FILE.png]: the statistics of\n"
      "docs/twin.md measured on both, side by side with their ratio (TWIN: a twin folder or a\n"
      "dataset): scan_rate_hz, beams_per_scan_mean, no_return_fraction,\n"
      "scan_to_map_residual_median_m, scan_to_map_residual_p95_m,\n"
      "scan_residual_neighbour_correlation, scan_residual_revisit_correlation,\n"
      "scan_transient_fraction, match_converged_percent, odometry_drift_per_m, "
      "odometry_step_noise_deg,\n"
      "wheels_vs_scans_residual_deg, calibration_sigma_b, calibration_b_m.");
  cli->add_option("DATASET", flags->dataset, "the recording (an imported dataset; read only)");
  cli->add_option("--out", flags->out, "the twin's folder")->check(outputPath());
  cli->add_option("--calibration", flags->calibration,
                  "the twin's true geometry from this calibration JSON (calibrate --json)");
  cli->add_flag("--no-calibrate", flags->no_calibrate,
                "without --calibration: the nominal geometry is the truth (no calibration run)");
  cli->add_option("--deskew", flags->params.deskew,
                  "how the scans are matched for the map (slamprep match --deskew)")
      ->capture_default_str();
  cli->add_option("--seed", flags->params.seed, "the twin's noise seed")->capture_default_str();
  cli->add_option("--compare", flags->compare, "REAL TWIN: compare a recording with its twin")
      ->expected(2);
  addJson(cli, *flags, "the comparison (with --compare only)");
  cli->add_option("--plot", flags->plot, "with --compare: draw the ratios (PNG)")
      ->check(outputPath());
  addForce(cli, *flags, "an existing --out twin folder, or --json and --plot files");
  addQuiet(cli, *flags);
  return {cli, [flags] { return run(*flags); }};
}

}  // namespace slamprep::app
