#pragma once
// The calibration pipeline on a dataset (`slamprep calibrate`, the bench): the lidar motion the
// interval methods consume, and the whole run from directories to method results.

#include <optional>
#include <string>
#include <vector>

#include "slamprep/algo/agreement/sensor_agreement.hpp"
#include "slamprep/algo/calibration/calibration.hpp"
#include "slamprep/algo/calibration/calibration_json.hpp"
#include "slamprep/algo/calibration/dataset_motion.hpp"
#include "slamprep/algo/matching/loop_closure.hpp"
#include "slamprep/algo/timing/dataset_stamps.hpp"
#include "slamprep/core/dataset.hpp"
#include "slamprep/core/enum_names.hpp"
#include "slamprep/eval/formats/wheel_odometry.hpp"

namespace slamprep::eval {

/// Where the lidar motion for calibration comes from.
enum class MotionSource {
  kIcp,  ///< chained scan-to-scan ICP
  /// The scan-to-map trajectory of `slamprep match` (without its fusion with the odometry, which
  /// would pull the motion toward the geometry being calibrated); fallbacks break the chain.
  /// Sparse real scans match a map far more often than each other (docs/calibration.md
  /// "Scan-to-map motion").
  kMap,
  kGroundTruth,  ///< the true poses (an oracle run)
};
/// As `calibrate --motion` and a suite's `motion` spell them.
inline constexpr auto kMotionSourceNames = std::to_array<EnumName<MotionSource>>({
    {MotionSource::kIcp, "icp"},
    {MotionSource::kMap, "map"},
    {MotionSource::kGroundTruth, "groundtruth"},
});

struct CalibrationMotionOptions {
  /// The bench's (its suites' honest sigma was measured with chained matches); `slamprep
  /// calibrate` sets kMap, its default (docs/calibration.md "Scan-to-map motion").
  MotionSource source = MotionSource::kIcp;
  /// Match scans de-skewed with this method first. "auto": the gyro (imu) when the log has one,
  /// since it does not depend on the wheel geometry being calibrated (de-skewing with the wrong
  /// geometry biased the mount yaw by 0.12 deg on 3 minutes of driving; imu: 0.02 deg), else
  /// odom-linear; none when the scans are instantaneous (time_increment 0, e.g. CARMEN logs).
  /// "none": raw scans, biased by the distortion itself.
  std::string deskew = "auto";
  bool stamp_is_last_beam = false;  ///< the scans' stamps mark their last beam
  /// How intervals are cut; `slamprep calibrate` and the bench both keep the defaults (one
  /// interval per scan match), so the same log gives them the same intervals.
  algo::IntervalParams intervals;
  /// The scan matcher between consecutive scans (the library's defaults unless overridden).
  algo::IcpParams icp;
  /// Match scans where a chain revisits a place directly and spread the heading drift this
  /// reveals back over the chain (`calibrate --loop-closure`, docs/calibration.md).
  bool loop_closure = false;
  algo::LoopClosureParams loops;  ///< its `icp` is replaced by `icp` above
};

/// What loop closure did to the chains, summed over them.
struct LoopClosureSummary {
  int used = 0;                      ///< direct matches that corrected the chains
  int candidates = 0;                ///< pairs matched directly (used + refused)
  double max_link_change_rad = 0.0;  ///< the largest heading change of one link
};

struct CalibrationMotion {
  std::vector<algo::ScanMatch> matches;  ///< consecutive scans (none for ground truth)
  std::vector<PoseSeries> chains;        ///< T_world_lidar chains (one for ground truth)
  int failed_matches = 0;
  int sparse_scans = 0;  ///< of the failed (map motion): fewer points than ICP needs
  std::optional<LoopClosureSummary> loops;    ///< with loop_closure
  std::vector<algo::LoopSpan> heading_loops;  ///< the spans the loop closures corrected
  algo::IntervalSet intervals;
};

/// Lidar motion and intervals from a dataset (de-skew with the nominal geometry, as the robot
/// believes, then point-to-line ICP between consecutive scans; or ground truth).
CalibrationMotion calibrationMotion(const Dataset& dataset,
                                    const CalibrationMotionOptions& options);

/// What `slamprep calibrate` runs.
struct DatasetCalibrationParams {
  std::string dataset;  ///< dataset directory; may be empty when `tuples` is given
  std::vector<algo::CalibrationMethod> methods = algo::allCalibrationMethods();
  /// Censi interval records to calibrate from instead of the dataset's motion.
  std::string tuples;
  /// More UMBmark square-run datasets (the dataset itself counts when it is one).
  std::vector<std::string> squares;
  CalibrationMotionOptions motion;
  algo::CalibrationParams params;
  /// The geometry the odometry is taken to use (`--nominal`); unset: dataset.json's. On a log
  /// without encoder ticks the wheel increments are derived from the odometry poses with it.
  std::optional<DiffDriveParams> nominal;
  /// Put measurably jittered stamps of constant-rate streams back on their grids first
  /// (`--stamps auto`, algo/timing/dataset_stamps.hpp); false: the stamps as logged.
  bool regularize_stamps = true;
  /// Compare the wheels, the gyro and the scan-matched motion first (algo/agreement) and refuse
  /// every method where the wheels and the gyro disagree beyond any wheel geometry ...
  bool refuse_on_disagreement = true;
  /// ... or, instead, leave out the intervals that overlap the disagreeing spans.
  bool exclude_disagreement = false;
  /// Move the wheels' stamps onto the scans' clock by the delay the sensor agreement measures
  /// between them, where it exceeds min_sync_lag_s (`--sync auto`; docs/calibration.md).
  bool sync_clocks = true;
  double min_sync_lag_s = 0.02;
  double min_refine_lag_s = 0.005;  ///< what is left after a sync, moved again from here
  /// Take the dataset's lidar mount as known in the methods that do not estimate one (direct,
  /// model; `--lidar-mount dataset`); false: they assume the lidar at the robot centre.
  bool mount_from_dataset = false;
  /// Fuse the dataset's measured mount (DatasetCalibration::lidar_mount_from not empty) into
  /// joint and ceres as a prior with these 1-sigmas (`--mount-prior`, algo/calibration/
  /// mount_prior.hpp); false: the intervals alone.
  bool mount_prior = true;
  double mount_prior_sigma_xy_m = 0.02;
  double mount_prior_sigma_yaw_rad = 0.035;
  /// Run only the methods whose input is there (`--method all`); the others are listed in
  /// DatasetCalibration::not_applicable instead of refusing.
  bool only_applicable = false;
};

/// A method left out because the data lacks its input (algo::missingInput).
struct NotApplicable {
  algo::CalibrationMethod method;
  std::string reason;
};

struct DatasetCalibration {
  std::vector<algo::CalibrationRun> runs;     ///< one per method run, in the order asked
  std::vector<NotApplicable> not_applicable;  ///< with only_applicable: the methods left out
  algo::IntervalSet intervals;                ///< what the interval methods used, what was dropped
  bool from_motion = false;  ///< the intervals were cut from the dataset's motion (no tuples)
  int failed_matches = 0;    ///< scan matches that broke a chain
  int sparse_scans = 0;      ///< of those: fewer points than ICP needs (the lidar saw little)
  std::optional<LoopClosureSummary> loops;  ///< with --loop-closure
  /// The wheels, gyro, odometry topic and scan-matched motion compared (from the dataset's
  /// motion only, not --tuples), and where the wheels came from (algo::encodersFrom).
  std::optional<algo::SensorAgreement> agreement;
  std::string encoders_from;
  std::size_t intervals_excluded = 0;  ///< with exclude_disagreement
  double clock_offset_s = 0.0;  ///< what sync_clocks added to the wheels' stamps (0: nothing)
  std::vector<algo::StreamStamps> stamps;       ///< what stamp regularisation found and did
  std::optional<algo::CalibrationTruth> truth;  ///< when the dataset knows its true geometry
  /// Set when the log had no encoder ticks: the geometry the wheel increments were derived from
  /// its odometry poses with (every interval run carries it as relative_to_odometry).
  std::optional<DiffDriveParams> relative_to_odometry;
  /// The encoders the intervals were cut from (derived ones for a log without ticks), and the
  /// nominal odometry pose at their first stamp: what calibratedOdometry() integrates.
  OdometryEncoders odometry;
  DiffDriveParams nominal;  ///< the geometry the odometry uses (--nominal, else dataset.json's)
  SE2 T_base_lidar;         ///< the dataset's lidar mount (dataset.json)
  /// Where that mount was measured (config "lidar_mount_from": a tf, --lidar-mount, a log's
  /// PARAM lines); empty when the dataset gave none (identity) or is simulated.
  std::string lidar_mount_from;
};

/// The encoders of `c` integrated with `geometry` from the nominal odometry's pose at their first
/// stamp: T_odom_base at every encoder stamp (`calibrate --odometry-out`; eval::integrateOdometry,
/// the function `export --calibration` uses too).
PoseSeries calibratedOdometry(const DatasetCalibration& c, const DiffDriveParams& geometry);

/// Reads the dataset (and square runs), builds the methods' inputs and runs them. Throws
/// InputError naming the directory or file for bad input (before any matching is done).
/// `dataset`: the dataset already in memory (e.g. the calibration part of a recording split for
/// validation) instead of reading params.dataset, which then only names it in messages.
DatasetCalibration calibrateDataset(const DatasetCalibrationParams& params,
                                    std::optional<Dataset> dataset = std::nullopt);

}  // namespace slamprep::eval
