#include "eval/bench/trial.hpp"

#include <chrono>
#include <cmath>
#include <numbers>

#include "algo/calibration/calibrate.hpp"
#include "algo/calibration/dataset_motion.hpp"
#include "algo/timing/dataset_stamps.hpp"
#include "core/error.hpp"
#include "core/odometry.hpp"
#include "core/stage_report.hpp"
#include "eval/bench/fault_score.hpp"
#include "eval/metrics/calibration_error.hpp"
#include "eval/metrics/consistency.hpp"
#include "eval/metrics/odometry_drift.hpp"
#include "eval/metrics/trajectory_error.hpp"
#include "eval/pipeline/calibration_run.hpp"
#include "eval/pipeline/dataset_deskew.hpp"
#include "eval/pipeline/deskew_json.hpp"
#include "eval/pipeline/match_run.hpp"
#include "sim/drive/simulator.hpp"

namespace slamprep::eval {
namespace {

using nlohmann::json;
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

json simJson(const sim::SimSummary& s) {
  return {{"duration_s", s.duration_s},
          {"scans", s.scans},
          {"beams", s.beams},
          {"distance_m", s.distance_m},
          {"turned_rad", s.rotation_rad},
          {"mean_abs_yaw_rate_radps", s.duration_s > 0 ? s.rotation_rad / s.duration_s : 0.0},
          {"mean_speed_mps", s.duration_s > 0 ? s.distance_m / s.duration_s : 0.0},
          {"drift_nominal_m", s.drift_nominal.final_position_error_m},
          {"drift_true_m", s.drift_true.final_position_error_m}};
}

// Error of every scan-to-scan match against the true lidar motion.
json matchingJson(const Dataset& dataset, const CalibrationMotion& motion) {
  const ScanMatchError e = scanMatchError(motion.matches, algo::lidarPosesFromGroundTruth(dataset));
  const double converged_fraction = e.pairs > 0 ? static_cast<double>(e.converged) / e.pairs : 0.0;
  json out = {{"pairs", e.pairs}, {"converged_fraction", converged_fraction}};
  if (e.translation_m.ok)
    out.update({{"trans_error_m_mean", e.translation_m.mean},
                {"trans_error_m_rmse", e.translation_m.rmse},
                {"rot_error_deg_mean", e.rotation_deg.mean},
                {"rot_error_deg_rmse", e.rotation_deg.rmse}});
  if (motion.loops)
    out["loop_closure"] = {
        {"used", motion.loops->used},
        {"candidates", motion.loops->candidates},
        {"max_link_change_deg", motion.loops->max_link_change_rad * 180.0 / std::numbers::pi}};
  return out;
}

// Dead-reckoning error against the truth, as evo computes it: APE after putting the first poses
// together (--align_origin), RPE per metre driven.
json odometryJson(const PoseSeries& odom, const PoseSeries& truth) {
  const ApeResult ape = absolutePoseError(odom, truth, {.align = false, .align_origin = true});
  const RpeResult rpe = relativePoseError(odom, truth, {.delta = 1.0, .unit = DeltaUnit::kMeters});
  json out = json::object();
  if (ape.ok)
    out.update({{"ape_rmse_m", ape.translation_m.rmse}, {"ape_max_m", ape.translation_m.max}});
  if (rpe.ok)
    out.update({{"rpe_trans_rmse_m", rpe.translation_m.rmse},
                {"rpe_rot_rmse_deg", rpe.rotation_deg.rmse}});
  return out;
}

// Estimate, sigma and absolute error of one method, plus the drift with its geometry.
json calibrationJson(const Dataset& dataset, const algo::CalibrationResult& result) {
  if (!result.ok) {
    json refused = {{"ok", false}, {"reason", result.reason}};
    // With faults injected, a refusal counts as robust only when it names one of them.
    if (dataset.info.faults.is_object())
      refused["refusal_names_fault"] = namesInjectedFault(result.reason, dataset);
    return refused;
  }
  CalibrationEstimate estimate{result.geometry, std::nullopt, std::nullopt, std::nullopt};
  const Eigen::VectorXd sigma = result.sigma();
  if (sigma.size() >= 3) estimate.geometry_sigma = sigma.head<3>();
  if (result.estimates_mount) {
    estimate.T_base_lidar = result.T_base_lidar;
    if (sigma.size() >= 6) estimate.mount_sigma = sigma.segment<3>(3);
  }
  const auto error =
      calibrationError(estimate, *dataset.info.true_geometry, dataset.info.T_base_lidar);
  json out = {{"ok", true}, {"condition_number", result.condition_number}};
  static const std::map<std::string, std::pair<std::string, double>> kKeys = {
      {"r_L", {"r_L_pct", 100.0}},      {"r_R", {"r_R_pct", 100.0}},
      {"b", {"b_pct", 100.0}},          {"mount_x", {"lidar_x_mm", 1.0}},
      {"mount_y", {"lidar_y_mm", 1.0}}, {"mount_yaw", {"lidar_yaw_deg", 1.0}}};
  Eigen::VectorXd error_si(static_cast<Eigen::Index>(error.parameters.size()));
  for (std::size_t i = 0; i < error.parameters.size(); ++i) {
    const auto& p = error.parameters[i];
    const auto& [key, scale] = kKeys.at(p.name);
    out["abs_error"][key] = std::abs(p.error) * scale;
    out["signed_error"][key] = p.error * scale;
    if (p.sigma) out["sigma"][key] = *p.sigma * scale;
    error_si(i) = p.error * (p.unit == "relative" ? p.truth
                             : p.unit == "mm"     ? 1e-3
                                                  : std::numbers::pi / 180);
  }
  // NEES over the parameters the method estimates, with its full covariance (SI units).
  const auto k = error_si.size();
  if (result.covariance.rows() >= k && result.covariance.cols() >= k)
    if (const auto nees = normalizedErrorSquared(error_si, result.covariance.topLeftCorner(k, k)))
      out["nees"] = *nees;
  if (error.all_within_3_sigma) out["inside_3sigma"] = *error.all_within_3_sigma;
  const PoseSeries odom =
      integrateEncoders(dataset.encoders, result.geometry, dataset.info.ticks_per_revolution);
  const DriftResult drift = odometryDrift(odom, dataset.groundtruth);
  if (drift.ok) out["drift_m"] = drift.final_position_error_m;
  out.update(odometryJson(odom, dataset.groundtruth));
  return out;
}

// `refusals` is an array (never summarised); `refused_by_reason` counts enter the summary, and
// only the figures measured do (no nulls).
json deskewJson(const DatasetDeskew& d, const std::string& method) {
  json out = {{"ok", d.refused == 0}};
  if (d.refused) {
    out["refused_scans"] = d.refused;
    out["refused_by_reason"] = refusedByReason(d.refusals);
    out["refusals"] = json(deskewRefusalsJson(d, method));
  }
  out.update(json(deskewFiguresJson(d, AbsentFigure::kOmitted)));
  return out;
}

// The geometry the odometry-based de-skew methods use in this trial.
DiffDriveParams deskewGeometry(const Suite& suite, const Dataset& dataset,
                               const algo::CalibrationRun* best) {
  if (suite.deskew_geometry == "true") return *dataset.info.true_geometry;
  if (suite.deskew_geometry == "calibrated" && best) return best->result.geometry;
  return dataset.info.nominal_geometry;
}

json xyArray(const std::vector<Eigen::Vector2d>& points) {
  json out = json::array();
  for (const auto& p : points) out.push_back({p.x(), p.y()});
  return out;
}

// Positions of a trajectory every `step_s` (plots need no more).
json decimated(const PoseSeries& poses, double step_s) {
  std::vector<Eigen::Vector2d> points;
  double next = -1e300;
  for (const auto& s : poses.samples())
    if (s.stamp_s >= next) {
      points.push_back(s.value.translation());
      next = s.stamp_s + step_s;
    }
  return xyArray(points);
}

// Dead-reckoning error against the truth every `step_s`, with both started on the true start
// pose (evo's APE, aligned at the first pose): {"t", "translation_m", "heading_deg"}.
json odometryErrorJson(const PoseSeries& truth, const PoseSeries& odometry_world, double step_s) {
  json out = {
      {"t", json::array()}, {"translation_m", json::array()}, {"heading_deg", json::array()}};
  double next = -1e300;
  for (const auto& s : odometry_world.samples()) {
    if (s.stamp_s < next) continue;
    const auto T_true = truth.at(s.stamp_s);
    if (!T_true) continue;
    const SE2 e = T_true->inverse() * s.value;
    out["t"].push_back(s.stamp_s);
    out["translation_m"].push_back((s.value.translation() - T_true->translation()).norm());
    out["heading_deg"].push_back(e.yaw * 180.0 / std::numbers::pi);
    next = s.stamp_s + step_s;
  }
  return out;
}

// The scan whose true lidar turned most while it was taken: where distortion shows best.
std::size_t mostDistortedScan(const Dataset& dataset) {
  std::size_t best = 0;
  double best_turn = -1.0;
  for (std::size_t k = 0; k < dataset.scans.size(); ++k) {
    const auto& scan = dataset.scans[k].scan;
    const auto a = dataset.groundtruth.at(scan.stamp_s), b = dataset.groundtruth.at(scan.endTime());
    if (a && b && std::abs(between(*a, *b).yaw) > best_turn) {
      best_turn = std::abs(between(*a, *b).yaw);
      best = k;
    }
  }
  return best;
}

// Trajectories and one scan (raw, de-skewed, true) in the world frame, for the suite's plots.
json artifactsJson(const Dataset& dataset, const DiffDriveParams* calibrated,
                   const std::string& calibrated_method, const DatasetDeskew* deskewed,
                   const std::string& deskew_method) {
  const double step_s = 0.1;
  json out;
  out["trajectory"]["true"] = decimated(dataset.groundtruth, step_s);
  const int ticks = dataset.info.ticks_per_revolution;
  const auto addOdometry = [&](const char* name, const DiffDriveParams& geometry) {
    const PoseSeries odom = integrateEncoders(dataset.encoders, geometry, ticks);
    const PoseSeries world =
        inWorld(odom, anchorOnTruth(odom, dataset.groundtruth).value_or(SE2()));
    out["trajectory"][name] = decimated(world, step_s);
    out["odometry_error"][name] = odometryErrorJson(dataset.groundtruth, world, step_s);
  };
  addOdometry("nominal", dataset.info.nominal_geometry);
  if (calibrated) {
    addOdometry("calibrated", *calibrated);
    out["trajectory"]["calibrated_method"] = calibrated_method;
  }
  const std::size_t k = mostDistortedScan(dataset);
  const ScanRecord& record = dataset.scans[k];
  const auto T_world_base = dataset.groundtruth.at(record.scan.stamp_s);
  if (!T_world_base) return out;
  const SE2 T_world_lidar = *T_world_base * dataset.info.T_base_lidar;
  const auto toWorld = [&](const std::vector<std::optional<Eigen::Vector2d>>& p_lidar) {
    std::vector<Eigen::Vector2d> points;
    for (const auto& p : p_lidar)
      if (p) points.push_back(T_world_lidar * *p);
    return xyArray(points);
  };
  std::vector<std::optional<Eigen::Vector2d>> raw;
  for (std::size_t i = 0; i < record.scan.size(); ++i)
    if (record.scan.valid(i)) raw.push_back(record.scan.point(i));
  out["scan"] = {{"index", k},
                 {"stamp_s", record.scan.stamp_s},
                 {"lidar", {T_world_lidar.x, T_world_lidar.y, T_world_lidar.yaw}},
                 {"raw", toWorld(raw)},
                 {"true", toWorld(record.p_ref_true)}};
  if (deskewed && deskewed->scans[k].ok) {
    out["scan"]["deskewed"] = toWorld(deskewed->scans[k].p_ref);
    out["scan"]["deskew_method"] = deskew_method;
  }
  return out;
}

// The methods' parameters: the defaults, plus the sideslip term when the suite asks for it.
algo::CalibrationParams calibrationParams(const Suite& suite) {
  algo::CalibrationParams params;
  params.joint.estimate_sideslip = params.ceres.estimate_sideslip = suite.calibration_sideslip;
  return params;
}

/// Simulates the trial's drive; its stamps regularised as calibrate and deskew do, its fault
/// events and its raw odometry (nominal and true geometry) reported.
Dataset simulateStage(const Suite& suite, const TrialSpec& spec, StageReporter& stages,
                      TrialOutput& out) {
  stages.begin("simulate");
  const auto start = Clock::now();
  const sim::SimResult sim =
      sim::simulate(simConfig(suite, spec), [&](double t_s, double duration_s) {
        if (duration_s > 0.0) stages.update(t_s / duration_s);
      });
  out.timing["simulate_s"] = secondsSince(start);
  out.result["sim"] = simJson(sim.summary);
  // Jittered stamps (the stamp_jitter fault) back on their grids, as calibrate and deskew do;
  // clean streams are left bit for bit, so clean trials are unchanged.
  Dataset dataset = sim.dataset;
  const auto stamps = algo::regularizeStamps(dataset);
  if (algo::anyApplied(stamps)) out.result["stamps"] = algo::stampsJson(stamps);
  if (const json events = faultEventCounts(dataset); !events.empty()) out.result["faults"] = events;
  const int ticks = dataset.info.ticks_per_revolution;
  for (const auto& [name, geometry] : {std::pair{"nominal", dataset.info.nominal_geometry},
                                       std::pair{"true", *dataset.info.true_geometry}})
    out.result["odometry"][name] =
        odometryJson(integrateEncoders(dataset.encoders, geometry, ticks), dataset.groundtruth);
  return dataset;
}

/// The suite's calibration methods on the trial's motion (ground truth or scan matching).
std::vector<algo::CalibrationRun> calibrateStage(const Suite& suite, const Dataset& dataset,
                                                 StageReporter& stages, TrialOutput& out) {
  std::vector<algo::CalibrationRun> calibrated;
  stages.begin("match");
  auto start = Clock::now();
  CalibrationMotionOptions motion_options;
  motion_options.source =
      parseName(kMotionSourceNames, suite.motion, "motion", suite.source.string() + ": motion");
  motion_options.loop_closure = suite.calibration_loop_closure;
  CalibrationMotion motion = calibrationMotion(dataset, motion_options);
  out.timing["motion_s"] = secondsSince(start);
  if (motion_options.source != MotionSource::kGroundTruth)
    out.result["matching"] = matchingJson(dataset, motion);
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
    out.timing["calibration"][name] = secondsSince(start);
    out.result["calibration"][name] = calibrationJson(dataset, calibrated.back().result);
    if (const auto& k = calibrated.back().sideslip_s)  // with calibration_sideslip
      out.result["calibration"][name]["sideslip_ms"] = {
          {"value", *k * 1e3}, {"sigma", calibrated.back().sideslip_sigma_s * 1e3}};
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
                        const algo::CalibrationRun* best, StageReporter& stages, TrialOutput& out) {
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
    out.timing["deskew"][name] = d.seconds;
    out.result["deskew"][name] = deskewJson(d, name);
    if (method != algo::DeskewMethod::kNone && method != algo::DeskewMethod::kOracle)
      shown = {std::move(d), name};
  }
  return shown;
}

TrialOutput runTrial(const Suite& suite, const TrialSpec& spec) {
  TrialOutput out;
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
    out.result["artifacts"] =
        artifactsJson(dataset, best ? &best->result.geometry : nullptr,
                      best ? std::string(algo::calibrationMethodName(best->method)) : std::string(),
                      shown.deskew ? &*shown.deskew : nullptr, shown.method);
  return out;
}

}  // namespace

TrialFunction benchTrial(const Suite& suite) {
  return [suite](const TrialSpec& spec) { return runTrial(suite, spec); };
}

}  // namespace slamprep::eval
