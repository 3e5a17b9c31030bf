#pragma once
// An experiment suite (eval/suites/<name>.yaml): which worlds, scenarios, sweeps, seeds and
// methods to run, expanded into a deterministic list of trials.

#include <cstdint>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slamprep/algo/calibration/calibration_method.hpp"

namespace slamprep::eval {

/// One swept simulator key and the values it takes (applied with `--set key=value`).
struct SweepAxis {
  std::string key;
  std::vector<std::string> values;
};

/// Regression tolerance for one summary metric (its mean over trials): a regression is a move
/// in the worse direction by more than max(abs, rel * |baseline|).
struct Tolerance {
  std::string metric;             ///< summary key, e.g. "deskew/odom-linear/mean_m"
  double abs = 0.0;               ///< absolute slack
  double rel = 0.0;               ///< slack relative to the baseline value
  bool higher_is_better = false;  ///< true for rates such as "calibration/joint/ok"
};

struct Suite {
  std::string name;
  std::string description;
  std::filesystem::path source;            ///< the YAML file
  std::vector<std::string> worlds;         ///< world files, relative to the repository root
  std::vector<std::string> scenarios;      ///< scenario files
  std::map<std::string, std::string> set;  ///< fixed simulator overrides for every trial
  std::vector<SweepAxis> sweep;            ///< cartesian product of all axes
  int seeds = 1;                           ///< seeds per sweep point
  std::uint64_t base_seed = 1;             ///< seed of the first trial; others follow
  double duration_s = 0.0;                 ///< 0: the scenario's own length
  std::string mode = "physics";            ///< physics | kinematic
  std::string motion = "icp";              ///< calibration motion source: icp | groundtruth
  std::vector<algo::CalibrationMethod> calibration_methods;  ///< interval methods only
  /// joint and ceres also estimate a sideslip k (calibrate --sideslip, docs/calibration.md).
  bool calibration_sideslip = false;
  /// Scan-matched motion gets its heading drift removed by loop closures first (calibrate
  /// --loop-closure, docs/calibration.md).
  bool calibration_loop_closure = false;
  std::vector<std::string> deskew_methods;
  /// Wheel geometry the odometry-based de-skew methods use: nominal | true | calibrated.
  std::string deskew_geometry = "nominal";
  std::vector<Tolerance> tolerances;
};

/// One run of the simulator and the methods, fully determined by its fields.
struct TrialSpec {
  std::size_t index = 0;  ///< position in the suite's expansion
  std::string id;         ///< stable, file-name safe
  std::string world;
  std::string scenario;
  std::map<std::string, std::string> overrides;  ///< suite `set` plus this trial's sweep values
  std::map<std::string, std::string> sweep;      ///< this trial's sweep values only
  std::uint64_t seed = 0;
  double duration_s = 0.0;
  /// The suite's settings every trial runs with (suiteSettings): stored with the result, so a
  /// suite edited (mode, methods, ...) makes the stored results stale instead of reused.
  nlohmann::json settings;
  /// Digests of the world and scenario files' bytes (attachInputDigests); null when not taken.
  nlohmann::json inputs;
};

/// Reads a suite YAML; throws InputError naming file, line and key.
Suite loadSuite(const std::filesystem::path& file);

/// Reads every world and scenario the suite names, so that a typo is refused (InputError naming
/// the suite, the key and the file) before any trial runs rather than failing every trial.
void checkSuiteFiles(const Suite& suite);

/// Resolves a suite name ("default") or path to its file under `suites_dir`.
std::filesystem::path findSuite(const std::string& name_or_path,
                                const std::filesystem::path& suites_dir);

/// Worlds x scenarios x sweep points x seeds, in that nesting order.
std::vector<TrialSpec> expandTrials(const Suite& suite);

/// What a trial depends on in the suite besides its own spec: mode, motion, the calibration and
/// de-skew methods and their options.
nlohmann::json suiteSettings(const Suite& suite);

/// Sets every trial's `inputs` to the FNV-1a digests of its world and scenario files (found as
/// the simulator finds them); a file that cannot be read gets "unreadable". The files a scenario
/// includes are not part of it.
void attachInputDigests(std::vector<TrialSpec>& trials);

}  // namespace slamprep::eval
