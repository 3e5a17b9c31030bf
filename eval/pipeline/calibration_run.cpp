#include "slamprep/eval/pipeline/calibration_run.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>

#include "slamprep/algo/agreement/agreement_report.hpp"
#include "slamprep/algo/agreement/dataset_sources.hpp"
#include "slamprep/algo/calibration/dataset_motion.hpp"
#include "slamprep/algo/matching/keyframe_odometry.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/eval/pipeline/dataset_deskew.hpp"
#include "slamprep/eval/pipeline/match_trajectory.hpp"

namespace slamprep::eval {
namespace {

/// `--deskew` resolved: auto is none on instantaneous scans (time_increment 0, e.g. CARMEN),
/// else imu where the log has one (independent of the geometry being calibrated), else
/// odom-linear.
algo::DeskewMethod deskewMethodFor(const Dataset& dataset, const std::string& deskew) {
  const bool instantaneous =
      !dataset.scans.empty() && dataset.scans.front().scan.time_increment_s == 0.0;
  const std::string name = deskew != "auto"      ? deskew
                           : instantaneous       ? "none"
                           : dataset.imu.empty() ? "odom-linear"
                                                 : "imu";
  return parseName(algo::kDeskewMethodNames, name, "de-skew method", "--deskew");
}

/// T_world_lidar of the scans `match` tracks against its map, fusion off; a chain ends at every
/// fallback (its pose is a guess, not a measurement).
std::vector<PoseSeries> mapChains(const Dataset& dataset, const CalibrationMotionOptions& options,
                                  int& fallbacks, int& sparse) {
  const algo::DeskewMethod method = deskewMethodFor(dataset, options.deskew);
  MatchTrajectoryOptions match;
  match.stamp_is_last_beam = options.stamp_is_last_beam;
  match.params.odometry_sigma_m = 0.0;
  match.params.odometry_sigma_rad = 0.0;
  const MatchTrajectory run =
      matchTrajectory(dataset,
                      matchScanPoints(dataset, std::string(algo::deskewMethodName(method)),
                                      options.stamp_is_last_beam),
                      match);
  sparse = static_cast<int>(run.tracked.sparse);
  std::vector<PoseSeries> chains(1);
  for (std::size_t k = 0; k < run.tracked.scans.size(); ++k) {
    if (run.tracked.scans[k].fallback) {
      ++fallbacks;
      if (!chains.back().empty()) chains.emplace_back();
      continue;
    }
    chains.back().push_back(run.pose_time_s[k], run.tracked.scans[k].T_world_lidar);
  }
  std::erase_if(chains, [](const PoseSeries& c) { return c.size() < 2; });
  return chains;
}

/// Leaves out the intervals that overlap a span where the wheels and the gyro disagree; returns
/// how many.
std::size_t dropDisagreeing(std::vector<algo::CalibrationInterval>& intervals,
                            const algo::PairAgreement& conflict) {
  const std::size_t before = intervals.size();
  std::erase_if(intervals, [&](const algo::CalibrationInterval& in) {
    return std::any_of(
        conflict.disagreements.begin(), conflict.disagreements.end(),
        [&](const algo::Disagreement& d) { return in.t_start_s < d.t1_s && in.t_end_s > d.t0_s; });
  });
  return before - intervals.size();
}

/// Every method refused for the same reason: the data cannot calibrate (exit 3).
std::vector<algo::CalibrationRun> refusedRuns(const std::vector<algo::CalibrationMethod>& methods,
                                              const std::string& reason) {
  std::vector<algo::CalibrationRun> runs;
  for (const algo::CalibrationMethod m : methods) {
    algo::CalibrationRun run;
    run.method = m;
    run.result.reason = reason +
                        " No wheel geometry explains this; calibrating through it would return a "
                        "confident wrong geometry (--exclude-disagreement leaves those spans out)";
    runs.push_back(std::move(run));
  }
  return runs;
}

// A refused direct or model fit on a dataset whose lidar is turned away from the base's x axis:
// their centred-lidar assumption reads a backwards lidar as wheels driving the wrong way.
void hintMount(std::vector<algo::CalibrationRun>& runs, const SE2& T_base_lidar) {
  constexpr double kTurnedRad = std::numbers::pi / 4.0;
  if (std::abs(T_base_lidar.yaw) <= kTurnedRad) return;
  for (algo::CalibrationRun& run : runs)
    if (!run.result.ok && !algo::estimatesMount(run.method) && algo::isIntervalMethod(run.method))
      run.result.reason +=
          "; the dataset's lidar is mounted turned " +
          std::to_string(std::lround(T_base_lidar.yaw * 180.0 / std::numbers::pi)) +
          " deg, which this method, assuming the lidar at the robot centre, does "
          "not know: --lidar-mount dataset takes the dataset's mount as known";
}

// A refused interval fit whose scan matches failed mostly on scans too sparse for ICP: the
// reason says so, since "too few intervals" alone points at the drive, not at the lidar.
void hintSparseScans(std::vector<algo::CalibrationRun>& runs, const DatasetCalibration& c,
                     std::size_t scans) {
  const std::string cause = algo::sparseScansCause(std::size_t(c.sparse_scans), scans);
  if (cause.empty()) return;
  for (algo::CalibrationRun& run : runs)
    if (!run.result.ok && algo::isIntervalMethod(run.method)) run.result.reason += "; " + cause;
}

bool contains(const std::vector<algo::CalibrationMethod>& methods, algo::CalibrationMethod m) {
  return std::find(methods.begin(), methods.end(), m) != methods.end();
}

std::vector<algo::UmbmarkRun> umbmarkRuns(const DatasetCalibrationParams& params,
                                          const Dataset* dataset) {
  std::vector<algo::UmbmarkRun> runs;
  auto add = [&](const Dataset& d, const std::string& where) {
    if (d.info.scenario.find("umbmark") == std::string::npos) return false;
    const auto run = algo::umbmarkRunFromDataset(d);
    if (!run) throw InputError(where, "UMBmark run needs ground truth and nominal odometry");
    runs.push_back(*run);
    return true;
  };
  if (dataset) add(*dataset, params.dataset);
  for (const std::string& dir : params.squares)
    if (!add(readDataset(dir), dir))
      throw InputError(dir, "--square: not an UMBmark square-run dataset (scenario umbmark_*)");
  return runs;
}

// Each chain with the heading drift its loop closures reveal spread back (algo/matching/
// loop_closure.hpp); `scan_points`: every scan's points as matched.
LoopClosureSummary closeLoops(const std::vector<Points2>& scan_points,
                              const algo::LoopClosureParams& params, algo::MatchChains& chained,
                              std::vector<algo::LoopSpan>& spans) {
  LoopClosureSummary summary;
  for (std::size_t c = 0; c < chained.chains.size(); ++c) {
    std::vector<const Points2*> chain_points;
    for (const std::size_t scan : chained.scans[c]) chain_points.push_back(&scan_points[scan]);
    algo::LoopCorrection loops = algo::closeLoops(chained.chains[c], chain_points, params);
    summary.used += static_cast<int>(loops.loops.size());
    summary.candidates += loops.candidates;
    summary.max_link_change_rad = std::max(summary.max_link_change_rad, loops.max_link_change_rad);
    for (const algo::LoopClosure& loop : loops.loops)
      spans.push_back({chained.chains[c][loop.from].stamp_s, chained.chains[c][loop.to].stamp_s});
    chained.chains[c] = std::move(loops.T_world_lidar);
  }
  return summary;
}

// The config's "lidar_mount_from" where the importer found a mount (not "nothing: ...").
std::string measuredMountSource(const DatasetInfo& info) {
  const auto it = info.config.find("lidar_mount_from");
  if (it == info.config.end() || !it->is_string()) return "";
  const std::string from = it->get<std::string>();
  return from.starts_with("nothing") ? "" : from;
}

// What the dataset gives every method: the nominal geometry (on a log without ticks, that of
// the encoders derived from its odometry), the mount, the truth.
algo::CalibrationInput datasetInput(const DatasetCalibrationParams& params,
                                    std::optional<Dataset>& dataset, DatasetCalibration& out) {
  algo::CalibrationInput input;
  if (!dataset) return input;
  // A log with odometry poses but no encoder ticks (an imported CARMEN log): encoders derived
  // from the poses, so intervals can be cut; the estimates are then relative to the log's own
  // odometry geometry (docs/calibration.md).
  out.odometry = odometryEncoders(*dataset, params.dataset, params.nominal);
  out.relative_to_odometry = out.odometry.derived_with;
  if (out.relative_to_odometry) {
    dataset->encoders = out.odometry.encoders;
    dataset->info.nominal_geometry = *out.relative_to_odometry;
  }
  input.nominal = params.nominal.value_or(dataset->info.nominal_geometry);
  out.nominal = *input.nominal;
  out.T_base_lidar = dataset->info.T_base_lidar;
  out.lidar_mount_from = measuredMountSource(dataset->info);
  if (params.mount_from_dataset) input.known_T_base_lidar = dataset->info.T_base_lidar;
  if (params.mount_prior && !out.lidar_mount_from.empty())
    input.mount_prior =
        algo::MountPrior{out.T_base_lidar, out.lidar_mount_from, params.mount_prior_sigma_xy_m,
                         params.mount_prior_sigma_yaw_rad};
  if (dataset->info.true_geometry)
    out.truth = algo::CalibrationTruth{*dataset->info.true_geometry, dataset->info.trueMount()};
  return input;
}

/// Whether the scan-to-map motion of `options` de-skews with the wheels' or the gyro's motion,
/// read at their stamps: a de-skew the delay being measured corrupts. (The chained matches of
/// kIcp stand at the scans' stamps, not at mid-sweep where a scan as measured stands.)
bool mapMotionReadsClocks(const Dataset& d, const CalibrationMotionOptions& options) {
  if (options.source != MotionSource::kMap) return false;
  return eval::deskewReadsClocks(deskewMethodFor(d, options.deskew));
}

/// The motion on which the delay is measured: scans as measured, read at mid-sweep
/// (MatchTrajectory::pose_time_s). De-skewed with wheels 0.3 s late, the scans of a Neato twin
/// tracked so badly that no delay was found on 7 of 32 seeds (0 of 32 as measured).
CalibrationMotionOptions noDeskew(CalibrationMotionOptions options) {
  options.deskew = "none";
  return options;
}

/// The wheels and the gyro moved onto the scans' clock (algo::syncOntoScanClock), `motion`
/// matched again from the moved data; a ground-truth motion does not depend on the clocks, so
/// it is moved once and kept. Returns the wheels' shift (0: none).
double syncClocks(Dataset& used, const algo::SensorAgreement& first,
                  const DatasetCalibrationParams& params, CalibrationMotion& motion) {
  if (params.motion.source == MotionSource::kGroundTruth) {
    const algo::ClockShift shift = algo::scanClockShift(first, params.min_sync_lag_s);
    if (shift.any()) algo::shiftOntoScanClock(used, shift);
    return shift.wheels_s;
  }
  return algo::syncOntoScanClock(used, first, params.min_sync_lag_s, params.min_refine_lag_s,
                                 [&](const Dataset& synced) {
                                   motion = calibrationMotion(synced, params.motion);
                                   return motion.chains;
                                 });
}

// The intervals of the interval methods: read from --tuples, or cut from the dataset's motion
// (scan matching or the truth), with the sensor agreement and the clock sync on the way.
void cutIntervals(const DatasetCalibrationParams& params, std::optional<Dataset>& dataset,
                  DatasetCalibration& out, algo::CalibrationInput& input) {
  if (!params.tuples.empty()) {
    out.intervals.intervals = algo::readIntervalRecords(params.tuples);
    return;
  }
  const Dataset& d = *dataset;
  if (params.motion.source == MotionSource::kGroundTruth && !d.hasTruth())
    throw InputError(params.dataset, "--motion groundtruth: the dataset has no ground truth");
  // The motion from stamps back on their grids; every output keeps the log's own stamps.
  std::optional<Dataset> regular;
  if (params.regularize_stamps) {
    regular = d;
    out.stamps = algo::regularizeStamps(*regular);
  }
  Dataset& used = algo::anyApplied(out.stamps) ? *regular : *dataset;
  const bool measure_apart = params.sync_clocks && mapMotionReadsClocks(used, params.motion);
  CalibrationMotion motion =
      calibrationMotion(used, measure_apart ? noDeskew(params.motion) : params.motion);
  out.intervals = std::move(motion.intervals);
  out.from_motion = true;
  out.agreement = algo::compareSensors(algo::datasetSources(d, algo::scanPieces(motion.chains)));
  out.encoders_from = algo::encodersFrom(d.info);
  // Synced, the intervals are cut again from the (last) motion. A real robot's odometry reached
  // the log 0.1-0.35 s before its scans: an interval one scan period long then pairs the scans'
  // motion with the wheels' motion of another moment.
  if (params.sync_clocks) {
    out.clock_offset_s = syncClocks(used, *out.agreement, params, motion);
    if (out.clock_offset_s != 0.0) {
      out.intervals = algo::buildIntervals(used, motion.chains, params.motion.intervals);
    } else if (measure_apart) {  // no delay: the motion with the de-skew asked for
      motion = calibrationMotion(used, params.motion);
      out.intervals = std::move(motion.intervals);
    }
  }
  out.failed_matches = motion.failed_matches;
  out.sparse_scans = motion.sparse_scans;
  out.loops = motion.loops;
  input.heading_loops = std::move(motion.heading_loops);
}

// The methods asked for that can run; with only_applicable the others are listed, not refused.
std::vector<algo::CalibrationMethod> applicableMethods(const DatasetCalibrationParams& params,
                                                       const algo::CalibrationInput& input,
                                                       DatasetCalibration& out) {
  std::vector<algo::CalibrationMethod> applicable;
  for (const algo::CalibrationMethod m : params.methods) {
    const auto missing = params.only_applicable ? algo::missingInput(m, input) : std::nullopt;
    if (missing)
      out.not_applicable.push_back({m, *missing});
    else
      applicable.push_back(m);
  }
  return applicable;
}

}  // namespace

PoseSeries calibratedOdometry(const DatasetCalibration& c, const DiffDriveParams& geometry) {
  return integrateOdometry(c.odometry, geometry);
}

CalibrationMotion calibrationMotion(const Dataset& dataset,
                                    const CalibrationMotionOptions& options) {
  CalibrationMotion motion;
  if (options.source == MotionSource::kGroundTruth) {
    motion.chains.push_back(algo::lidarPosesFromGroundTruth(dataset, options.stamp_is_last_beam));
  } else if (options.source == MotionSource::kMap) {
    motion.chains = mapChains(dataset, options, motion.failed_matches, motion.sparse_scans);
  } else {
    const algo::DeskewMethod method = deskewMethodFor(dataset, options.deskew);
    std::vector<Points2> points;  // empty: the scans as measured
    DatasetDeskewOptions deskew = nominalDeskewOptions(dataset);
    deskew.stamp_is_last_beam = options.stamp_is_last_beam;
    if (method != algo::DeskewMethod::kNone)
      points = correctedPoints(deskewDataset(dataset, method, deskew));
    else if (options.loop_closure)  // extracted once, for the chain's and the loops' matches
      for (const ScanRecord& record : dataset.scans) points.push_back(record.scan.points());
    algo::ScanMotionParams matching;
    matching.stamp_is_last_beam = options.stamp_is_last_beam;
    matching.deskew.icp = options.icp;
    motion.matches = algo::matchConsecutiveScans(dataset, matching, points);
    algo::MatchChains chained = algo::chainMatches(motion.matches);
    if (options.loop_closure) {
      algo::LoopClosureParams loops = options.loops;
      loops.icp = options.icp;  // the direct matches use the chain's matcher
      motion.loops = closeLoops(points, loops, chained, motion.heading_loops);
    }
    motion.chains = std::move(chained.chains);
    motion.failed_matches = chained.failed_matches;
  }
  motion.intervals = algo::buildIntervals(dataset, motion.chains, options.intervals);
  return motion;
}

DatasetCalibration calibrateDataset(const DatasetCalibrationParams& params,
                                    std::optional<Dataset> dataset) {
  if (params.dataset.empty() && params.tuples.empty() && !dataset)
    throw InputError("DATASET", "give a dataset directory, --tuples FILE, or both");
  if (!dataset && !params.dataset.empty()) dataset = readDataset(params.dataset);
  DatasetCalibration out;
  algo::CalibrationInput input = datasetInput(params, dataset, out);
  const Dataset* d = dataset ? &*dataset : nullptr;
  if (contains(params.methods, algo::CalibrationMethod::kUmbmark))
    input.umbmark_runs = umbmarkRuns(params, d);
  const auto& methods = params.methods;
  if (std::any_of(methods.begin(), methods.end(), algo::isIntervalMethod))
    cutIntervals(params, dataset, out, input);
  input.intervals = out.intervals.intervals;
  const algo::PairAgreement* conflict =
      out.agreement ? out.agreement->wheelsGyroConflict() : nullptr;
  // Without a gyro, the wheels against the scans are left out, though never refused on.
  const algo::PairAgreement* spans =
      conflict || !out.agreement ? conflict : out.agreement->wheelsScansConflict();
  if (spans && params.exclude_disagreement)
    out.intervals_excluded = dropDisagreeing(input.intervals, *spans);
  const std::vector<algo::CalibrationMethod> applicable = applicableMethods(params, input, out);
  if (conflict && params.refuse_on_disagreement && !params.exclude_disagreement) {
    out.runs = refusedRuns(applicable, algo::wheelsGyroConflictText(*out.agreement));
    return out;
  }
  out.runs = algo::calibrate(applicable, input, params.params);
  if (d && !params.mount_from_dataset) hintMount(out.runs, d->info.T_base_lidar);
  if (d) hintSparseScans(out.runs, out, d->scans.size());
  for (algo::CalibrationRun& run : out.runs)
    if (algo::isIntervalMethod(run.method)) run.relative_to_odometry = out.relative_to_odometry;
  return out;
}

}  // namespace slamprep::eval
