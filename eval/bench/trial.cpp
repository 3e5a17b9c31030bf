#include "slamprep/eval/bench/trial.hpp"

#include <chrono>

#include "slamprep/algo/calibration/calibrate.hpp"
#include "slamprep/algo/timing/dataset_stamps.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/core/stage_report.hpp"
#include "slamprep/eval/bench/fault_score.hpp"
#include "slamprep/eval/bench/trial_record.hpp"
#include "slamprep/eval/bench/trial_timing.hpp"
#include "slamprep/eval/pipeline/calibration_run.hpp"
#include "slamprep/eval/pipeline/dataset_deskew.hpp"
#include "slamprep/sim/drive/simulator.hpp"

namespace slamprep::eval {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

sim::SimConfig simConfig(const Suite& suite, const TrialSpec& spec) {
  sim::SimConfig config;
  config.world = spec.world;
  config.scenario = spec.scenario;
  config.seed = spec.seed;
  config.duration_s = spec.duration_s;
  config.mode = parseName(sim::kSimModeNames, suite.mode, "mode", suite.source.string() + ": mode");
  for (const auto& [key, value] : spec.overrides) sim::applyOverride(config, key + "=" + value);
  return config;
}

// The geometry the odometry-based de-skew methods use in this trial.
DiffDriveParams deskewGeometry(const Suite& suite, const Dataset& dataset,
                               const algo::CalibrationRun* best) {
  if (suite.deskew_geometry == "true") return *dataset.info.true_geometry;
  if (suite.deskew_geometry == "calibrated" && best) return best->result.geometry;
  return dataset.info.nominal_geometry;
}

// The methods' parameters: the defaults, plus the sideslip term when the suite asks for it.
algo::CalibrationParams calibrationParams(const Suite& suite) {
  algo::CalibrationParams params;
  params.joint.estimate_sideslip = params.ceres.estimate_sideslip = suite.calibration_sideslip;
  return params;
}

/// What a trial fills as it goes: its record and its stages' wall-clock times.
struct TrialProducts {
  TrialRecord record;
  TrialTiming timing;
};

/// Simulates the trial's drive; its stamps regularised as calibrate and deskew do, its fault
/// events and its raw odometry (nominal and true geometry) reported.
Dataset simulateStage(const Suite& suite, const TrialSpec& spec, StageReporter& stages,
                      TrialProducts& out) {
  stages.begin("simulate");
  const auto start = Clock::now();
  const sim::SimResult sim =
      sim::simulate(simConfig(suite, spec), [&](double t_s, double duration_s) {
        if (duration_s > 0.0) stages.update(t_s / duration_s);
      });
  out.timing.simulate_s = secondsSince(start);
  out.record.sim = simRecord(sim.summary);
  // Jittered stamps (the stamp_jitter fault) back on their grids, as calibrate and deskew do;
  // clean streams are left bit for bit, so clean trials are unchanged.
  Dataset dataset = sim.dataset;
  const auto stamps = algo::regularizeStamps(dataset);
  if (algo::anyApplied(stamps)) out.record.stamps = stampsRecord(stamps);
  out.record.faults = faultEventCounts(dataset);
  const auto odometry = [&](const DiffDriveParams& geometry) {
    return odometryRecord(
        integrateEncoders(dataset.encoders, geometry, dataset.info.ticks_per_revolution),
        dataset.groundtruth);
  };
  out.record.odometry_nominal = odometry(dataset.info.nominal_geometry);
  out.record.odometry_true = odometry(*dataset.info.true_geometry);
  return dataset;
}

/// The suite's calibration methods on the trial's motion (ground truth or scan matching).
std::vector<algo::CalibrationRun> calibrateStage(const Suite& suite, const Dataset& dataset,
                                                 StageReporter& stages, TrialProducts& out) {
  std::vector<algo::CalibrationRun> calibrated;
  stages.begin("match");
  auto start = Clock::now();
  CalibrationMotionOptions motion_options;
  motion_options.source =
      parseName(kMotionSourceNames, suite.motion, "motion", suite.source.string() + ": motion");
  motion_options.loop_closure = suite.calibration_loop_closure;
  CalibrationMotion motion = calibrationMotion(dataset, motion_options);
  out.timing.motion_s = secondsSince(start);
  if (motion_options.source != MotionSource::kGroundTruth)
    out.record.matching = matchingRecord(dataset, motion);
  algo::CalibrationInput input;
  input.intervals = std::move(motion.intervals.intervals);
  input.heading_loops = std::move(motion.heading_loops);
  input.nominal = dataset.info.nominal_geometry;
  stages.begin("calibrate");
  const algo::CalibrationParams params = calibrationParams(suite);
  for (const algo::CalibrationMethod method : suite.calibration_methods) {
    stages.update(static_cast<double>(calibrated.size()) / suite.calibration_methods.size());
    const std::string name(algo::calibrationMethodName(method));
    start = Clock::now();
    calibrated.push_back(algo::calibrate(method, input, params));
    out.timing.calibration[name] = secondsSince(start);
    out.record.calibration[name] = calibrationRecord(dataset, calibrated.back());
  }
  return calibrated;
}

/// What the scan plot shows: the last de-skew method run that is neither none nor the oracle.
struct ShownDeskew {
  std::optional<DatasetDeskew> deskew;
  std::string method;
};

/// The suite's de-skew methods with the best calibrated geometry (else the suite's).
ShownDeskew deskewStage(const Suite& suite, const Dataset& dataset,
                        const algo::CalibrationRun* best, StageReporter& stages,
                        TrialProducts& out) {
  DatasetDeskewOptions deskew_options = nominalDeskewOptions(dataset);
  deskew_options.geometry = deskewGeometry(suite, dataset, best);
  deskew_options.odometry = integrateEncoders(  // once, not once per method
      dataset.encoders, deskew_options.geometry, dataset.info.ticks_per_revolution);
  ShownDeskew shown;
  if (!suite.deskew_methods.empty()) stages.begin("deskew");
  for (std::size_t i = 0; i < suite.deskew_methods.size(); ++i) {
    const std::string& name = suite.deskew_methods[i];
    const auto method = parseName(algo::kDeskewMethodNames, name, "method",
                                  suite.source.string() + ": deskew_methods");
    deskew_options.on_scan = [&](std::size_t done, std::size_t total) {
      stages.update((i + static_cast<double>(done) / total) / suite.deskew_methods.size());
    };
    DatasetDeskew d = deskewDataset(dataset, method, deskew_options);
    out.timing.deskew[name] = d.seconds;
    out.record.deskew[name] = deskewRecord(d, name);
    if (method != algo::DeskewMethod::kNone && method != algo::DeskewMethod::kOracle)
      shown = {std::move(d), name};
  }
  return shown;
}

TrialOutput runTrial(const Suite& suite, const TrialSpec& spec) {
  TrialProducts out;
  const bool calibrates = !suite.calibration_methods.empty();
  StageReporter stages(spec.id, 1 + (calibrates ? 2 : 0) + (suite.deskew_methods.empty() ? 0 : 1));
  const Dataset dataset = simulateStage(suite, spec, stages, out);
  const std::vector<algo::CalibrationRun> calibrated =
      calibrates ? calibrateStage(suite, dataset, stages, out)
                 : std::vector<algo::CalibrationRun>{};
  const algo::CalibrationRun* best = algo::bestRun(calibrated);
  const ShownDeskew shown = deskewStage(suite, dataset, best, stages, out);
  stages.end();
  // Artifacts for the plots: only the first trial, to keep results small. Arrays never enter
  // the summary (only numeric leaves of objects do).
  if (spec.index == 0)
    out.record.artifacts = artifactsRecord(
        dataset, best ? &best->result.geometry : nullptr,
        best ? std::string(algo::calibrationMethodName(best->method)) : std::string(),
        shown.deskew ? &*shown.deskew : nullptr, shown.method);
  return {out.record, out.timing};
}

}  // namespace

TrialFunction benchTrial(const Suite& suite) {
  return [suite](const TrialSpec& spec) { return runTrial(suite, spec); };
}

}  // namespace slamprep::eval
