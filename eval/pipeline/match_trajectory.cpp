#include "slamprep/eval/pipeline/match_trajectory.hpp"

#include <chrono>
#include <nlohmann/json.hpp>
#include <string>

#include "slamprep/algo/agreement/dataset_sources.hpp"
#include "slamprep/algo/calibration/dataset_motion.hpp"
#include "slamprep/algo/deskew/deskew.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/heading.hpp"
#include "slamprep/eval/pipeline/calibration_run.hpp"
#include "slamprep/eval/pipeline/dataset_deskew.hpp"
#include "slamprep/eval/pipeline/match_run.hpp"

namespace slamprep::eval {
namespace {

/// What the odometry and the gyro say of each step between consecutive scans (index 0 unused).
std::vector<algo::StepPrior> stepPriors(const Dataset& dataset, const std::vector<double>& stamps_s,
                                        const MatchTrajectoryOptions& options) {
  std::vector<algo::StepPrior> priors(stamps_s.size());
  const HeadingSeries gyro = options.use_gyro ? gyroHeading(dataset.imu) : HeadingSeries();
  for (std::size_t k = 1; k < priors.size(); ++k) {
    priors[k].odometry = algo::odometryLidarMotion(dataset, stamps_s[k - 1], stamps_s[k]);
    if (!gyro.empty())
      priors[k].gyro_yaw_rad = turned(gyro, stamps_s[k - 1], stamps_s[k], options.max_gyro_gap_s);
  }
  return priors;
}

bool fused(const algo::KeyframeOdometryParams& p) {
  return p.odometry_sigma_m > 0.0 && p.odometry_sigma_rad > 0.0;
}

algo::KeyframeOdometryParams withoutFusion(algo::KeyframeOdometryParams p) {
  p.odometry_sigma_m = 0.0;
  p.odometry_sigma_rad = 0.0;
  return p;
}

/// The base poses of the accepted scans of `tracked` at the times they stand for.
PoseSeries acceptedPoses(const algo::KeyframeOdometry& tracked,
                         const std::vector<double>& pose_time_s, const SE2& T_base_lidar) {
  const SE2 T_lidar_base = T_base_lidar.inverse();
  PoseSeries accepted;
  for (std::size_t k = 0; k < tracked.scans.size(); ++k)
    if (!tracked.scans[k].fallback)
      accepted.push_back(pose_time_s[k], tracked.scans[k].T_world_lidar * T_lidar_base);
  return accepted;
}

/// options.params, with the odometry noise measured where asked (and fused at all): the scans
/// alone first, the odometry's noise measured against them (Eqs. 1-3 of
/// algo/matching/odometry_noise.hpp); that pass's accepted poses, which the sensor agreement
/// compares with the wheels, and the measurement go into `run`.
algo::KeyframeOdometryParams fusionParams(const ScanPoints& points,
                                          const std::vector<algo::StepPrior>& priors,
                                          const SE2& start, const SE2& T_base_lidar,
                                          const MatchTrajectoryOptions& options,
                                          MatchTrajectory& run) {
  algo::KeyframeOdometryParams params = options.params;
  if (!fused(params) || !options.measure_odometry_noise) return params;
  const algo::KeyframeOdometry alone =
      algo::trackKeyframes(points.points, priors, withoutFusion(params), start);
  run.scans_alone = acceptedPoses(alone, run.pose_time_s, T_base_lidar);
  run.odometry_noise = algo::measureOdometryNoise(alone, priors);
  if (run.odometry_noise) {
    params.odometry_sigma_m = run.odometry_noise->sigma_m;
    params.odometry_sigma_rad = run.odometry_noise->sigma_rad;
  }
  return params;
}

/// Whether the method de-skewed the scan: not where it refused or left it as measured (vicp's
/// first scan after a refusal, const-velocity's before any motion). A scan de-skewed with no
/// motion (odometry that stood still) was: its motion model puts it at the first beam.
bool deskewedToFirstBeam(const algo::DeskewResult& r) {
  return r.ok && !r.as_measured;
}

}  // namespace

ScanPoints matchScanPoints(const Dataset& d, const std::string& deskew, bool stamp_is_last_beam) {
  ScanPoints out;
  if (deskew == "none") {
    for (const ScanRecord& record : d.scans) out.points.push_back(record.scan.points());
    out.deskewed.assign(d.scans.size(), 0);
    return out;
  }
  const auto method = parseName(algo::kDeskewMethodNames, deskew, "de-skew method", "--deskew");
  DatasetDeskewOptions options = nominalDeskewOptions(d);
  if (d.encoders.empty()) options.odometry = d.odom_nominal;  // an imported log: its poses
  options.stamp_is_last_beam = stamp_is_last_beam;
  options.measure_errors = false;  // the points are matched; their errors are not wanted here
  const DatasetDeskew deskewed = deskewDataset(d, method, options);
  const std::vector<Points2> corrected = correctedPoints(deskewed);
  for (std::size_t k = 0; k < d.scans.size(); ++k) {
    const bool ok = deskewed.scans[k].ok;
    out.points.push_back(ok ? corrected[k] : d.scans[k].scan.points());
    out.deskewed.push_back(deskewedToFirstBeam(deskewed.scans[k]) ? 1 : 0);
  }
  out.refused = deskewed.refused;
  return out;
}

namespace {

/// What tracking needs besides the points: every step's guesses and the first scan's pose.
struct TrackingInput {
  std::vector<algo::StepPrior> priors;
  SE2 start;
};

/// `run`'s stamps, pose times and guess counts, and the input of its tracking. Throws
/// InputError when first-beam times do not increase.
TrackingInput prepareTracking(const Dataset& dataset, const ScanPoints& points,
                              const MatchTrajectoryOptions& options, MatchTrajectory& run) {
  for (std::size_t k = 0; k < dataset.scans.size(); ++k) {
    const LaserScan& scan = dataset.scans[k].scan;
    const double t = algo::firstBeamTime(scan, options.stamp_is_last_beam);
    if (!run.stamps_s.empty() && !(t > run.stamps_s.back()))
      throw InputError("scans.jsonl: scan " + std::to_string(run.stamps_s.size()),
                       "first-beam times not increasing");
    run.stamps_s.push_back(t);
    const double sweep_s = (scan.size() > 0 ? scan.size() - 1 : 0) * scan.time_increment_s;
    run.pose_time_s.push_back(points.deskewed.at(k) ? t : t + 0.5 * sweep_s);
  }
  TrackingInput in{stepPriors(dataset, run.stamps_s, options), SE2()};
  for (const algo::StepPrior& p : in.priors) {
    run.odometry_guesses += p.odometry ? 1 : 0;
    run.gyro_guesses += p.gyro_yaw_rad ? 1 : 0;
  }
  const auto odom0 = run.stamps_s.empty() ? std::nullopt : dataset.odom_nominal.at(run.stamps_s[0]);
  in.start = odom0.value_or(SE2()) * dataset.info.T_base_lidar;
  return in;
}

}  // namespace

MatchTrajectory matchTrajectory(const Dataset& dataset, const ScanPoints& points,
                                const MatchTrajectoryOptions& options) {
  MatchTrajectory run;
  const TrackingInput in = prepareTracking(dataset, points, options, run);
  const SE2& T_base_lidar = dataset.info.T_base_lidar;
  const auto begin = std::chrono::steady_clock::now();
  const algo::KeyframeOdometryParams params =
      fusionParams(points, in.priors, in.start, T_base_lidar, options, run);
  run.odometry_sigma_m = params.odometry_sigma_m;
  run.odometry_sigma_rad = params.odometry_sigma_rad;
  run.tracked = algo::trackKeyframes(points.points, in.priors, params, in.start);
  run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  const SE2 T_lidar_base = T_base_lidar.inverse();
  for (std::size_t k = 0; k < run.tracked.scans.size(); ++k)
    run.T_world_base.push_back(run.stamps_s[k], run.tracked.scans[k].T_world_lidar * T_lidar_base);
  return run;
}

std::optional<algo::OdometryNoise> measuredOdometryNoise(const Dataset& dataset,
                                                         const ScanPoints& points,
                                                         const MatchTrajectoryOptions& options) {
  MatchTrajectory run;
  const TrackingInput in = prepareTracking(dataset, points, options, run);
  return algo::measureOdometryNoise(
      algo::trackKeyframes(points.points, in.priors, withoutFusion(options.params), in.start),
      in.priors);
}

std::string formatTrackedMatches(const MatchTrajectory& run) {
  std::string text;
  for (std::size_t k = 1; k < run.tracked.scans.size(); ++k) {
    const algo::TrackedScan& s = run.tracked.scans[k];
    const algo::IcpResult& m = s.match;
    nlohmann::ordered_json line = matchLine(run.stamps_s[s.keyframe], run.stamps_s[k], m);
    line["fallback"] = s.fallback;
    line["keyframe"] = s.is_keyframe;
    line["map_points"] = s.map_points;
    line["guess"] = algo::guessSourceName(s.guess);
    line["hypotheses"] = s.hypotheses;
    line["support"] = s.support.fraction();
    text += line.dump() + "\n";
  }
  return text;
}

PoseSeries acceptedPoses(const MatchTrajectory& run) {
  PoseSeries accepted;
  for (std::size_t k = 0; k < run.tracked.scans.size(); ++k)
    if (!run.tracked.scans[k].fallback)
      accepted.push_back(run.pose_time_s[k], run.T_world_base[k].value);
  return accepted;
}

namespace {

/// `options` with the odometry fusion off: the scans alone.
MatchTrajectoryOptions scansAlone(MatchTrajectoryOptions options) {
  options.params = withoutFusion(options.params);
  return options;
}

}  // namespace

PoseSeries matchScansAlone(const Dataset& d, const std::string& deskew, bool stamp_is_last_beam) {
  return acceptedPoses(matchTrajectory(d, matchScanPoints(d, deskew, stamp_is_last_beam),
                                       scansAlone({{}, stamp_is_last_beam})));
}

PoseSeries scanOnlyPoses(const Dataset& dataset, const ScanPoints& points,
                         const MatchTrajectoryOptions& options, const MatchTrajectory& run) {
  if (run.scans_alone) return *run.scans_alone;
  if (!fused(options.params)) return acceptedPoses(run);
  return acceptedPoses(matchTrajectory(dataset, points, scansAlone(options)));
}

bool deskewReadsClocks(algo::DeskewMethod method) {
  const auto missing = algo::deskewMissingInput(method, {.groundtruth = true});
  return missing && *missing != algo::DeskewInput::kGroundTruth;
}

algo::SensorAgreement scanAgreement(const Dataset& dataset, const PoseSeries& scan_poses) {
  return algo::compareSensors(algo::datasetSources(dataset, algo::scanPieces({scan_poses})));
}

algo::SensorAgreement syncStartAgreement(const Dataset& dataset,
                                         const algo::SensorAgreement& matched,
                                         const std::string& deskew, bool stamp_is_last_beam) {
  const auto method = algo::parseDeskewMethod(deskew);
  if (!method || !deskewReadsClocks(*method)) return matched;
  return scanAgreement(dataset, matchScansAlone(dataset, "none", stamp_is_last_beam));
}

double syncOntoScans(Dataset& dataset, const std::string& deskew, bool stamp_is_last_beam) {
  return syncOntoScans(dataset,
                       scanAgreement(dataset, matchScansAlone(dataset, deskew, stamp_is_last_beam)),
                       deskew, stamp_is_last_beam);
}

double syncOntoScans(Dataset& dataset, const algo::SensorAgreement& first,
                     const std::string& deskew, bool stamp_is_last_beam) {
  const DatasetCalibrationParams thresholds;
  return algo::syncOntoScanClock(
      dataset, syncStartAgreement(dataset, first, deskew, stamp_is_last_beam),
      thresholds.min_sync_lag_s, thresholds.min_refine_lag_s, [&](const Dataset& d) {
        return std::vector<PoseSeries>{matchScansAlone(d, deskew, stamp_is_last_beam)};
      });
}

}  // namespace slamprep::eval
