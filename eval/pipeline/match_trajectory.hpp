#pragma once
// `slamprep match` on a dataset: scan-to-local-map lidar odometry (algo::trackKeyframes) guided
// by the dataset's odometry, its trajectory of the base, its per-scan lines and its summary
// (docs/matching.md).

#include <optional>
#include <string>
#include <vector>

#include "slamprep/algo/agreement/sensor_agreement.hpp"
#include "slamprep/algo/deskew/deskew.hpp"
#include "slamprep/algo/matching/keyframe_odometry.hpp"
#include "slamprep/algo/matching/odometry_noise.hpp"
#include "slamprep/core/dataset.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep::eval {

struct MatchTrajectoryOptions {
  algo::KeyframeOdometryParams params;
  bool stamp_is_last_beam = false;
  /// Guess each step's turn from the gyro too, where the dataset has an IMU ...
  bool use_gyro = true;
  /// ... and its samples lie no farther apart than this around the step.
  double max_gyro_gap_s = 0.25;
  /// Fuse with the odometry's noise measured on the recording (algo::measureOdometryNoise, a
  /// first pass with the fusion off) in place of params.odometry_sigma_*, which stay where too
  /// few steps measure it. No effect where the fusion is off (an odometry sigma of 0).
  bool measure_odometry_noise = true;
};

/// The matcher the twin module fits and compares with (eval/bench/twin*.cpp): the odometry
/// fused at the given noise, not the noise measured per recording. Held fixed so a twin's fit and
/// its statistics stay comparable from run to run; measured, it leaned on the TurtleBot4's /odom,
/// 0.17 s late, and the walls of that map fitted its scans worse (docs/twin.md).
inline MatchTrajectoryOptions twinMatchOptions() {
  MatchTrajectoryOptions options;
  options.measure_odometry_noise = false;
  return options;
}

struct MatchTrajectory {
  algo::KeyframeOdometry tracked;
  std::vector<double> stamps_s;  ///< first-beam time of every scan
  /// The time each scan's pose stands for: its first beam where the scan was de-skewed to it,
  /// the middle of its sweep where it was matched as measured. A rigid fit of a sweep made while
  /// turning sits between its first and last beams' poses; read at the first beam, a 5.7 Hz
  /// lidar's turning looked 88 ms later than the wheels' when it was not.
  std::vector<double> pose_time_s;
  PoseSeries T_world_base;           ///< the base at every scan's first beam (T_world_lidar l^-1)
  std::size_t odometry_guesses = 0;  ///< scans 1..n-1 with an odometry guess
  std::size_t gyro_guesses = 0;      ///< scans 1..n-1 with a gyro guess
  double seconds = 0.0;              ///< wall-clock time of the tracking
  /// The odometry noise per scan step the matches were fused with (0, 0: not fused) ...
  double odometry_sigma_m = 0.0;
  double odometry_sigma_rad = 0.0;
  /// ... and how it was measured (nullopt: as given).
  std::optional<algo::OdometryNoise> odometry_noise;
  /// The accepted poses of the first pass, the scans alone (acceptedPoses), where it was made.
  std::optional<PoseSeries> scans_alone;
};

/// Every scan's points in its first-beam lidar frame: as measured, or de-skewed by `deskew`
/// where the method applies; a scan it refuses (e.g. time_increment 0) is kept as measured and
/// counted in `refused`. What `slamprep match` tracks.
struct ScanPoints {
  std::vector<Points2> points;
  std::vector<char> deskewed;  ///< per scan: 1 de-skewed to its first beam, 0 as measured
  int refused = 0;
};
ScanPoints matchScanPoints(const Dataset& dataset, const std::string& deskew,
                           bool stamp_is_last_beam);

/// Tracks the scans given as `points` (one per dataset scan, in its first-beam lidar frame). The
/// guesses of scan k: the nominal odometry between the two first beams (algo::odometryLidarMotion,
/// as calibrate's matches use), the gyro's turn over them, the last step and standing still
/// (algo::trackKeyframes). The world frame is the odometry's at the first scan (the origin without
/// odometry). Throws InputError when first-beam times do not increase.
MatchTrajectory matchTrajectory(const Dataset& dataset, const ScanPoints& points,
                                const MatchTrajectoryOptions& options = {});

/// matches.jsonl (docs/matching.md): one object per scan after the first.
std::string formatTrackedMatches(const MatchTrajectory& run);

/// The poses of the scans whose match was accepted (a fallback's pose is a guess, not a
/// measurement), at the times they stand for (pose_time_s): what is compared with the wheels.
PoseSeries acceptedPoses(const MatchTrajectory& run);

/// The odometry's noise per scan step that `matchTrajectory` with `options` would measure
/// (algo::measureOdometryNoise on the scans tracked alone), without tracking them fused after.
std::optional<algo::OdometryNoise> measuredOdometryNoise(
    const Dataset& dataset, const ScanPoints& points, const MatchTrajectoryOptions& options = {});

/// The accepted poses of `deskew`'s scans matched alone, the default matcher with the fusion off:
/// what the clock sync and a twin's slip compare with the wheels.
PoseSeries matchScansAlone(const Dataset& dataset, const std::string& deskew,
                           bool stamp_is_last_beam);

/// What the scans say of the motion alone, for comparing it with the wheels: the accepted poses
/// of a match with the odometry fusion off (`run` itself where it was made so, its first pass
/// where it measured the odometry's noise). Fused, the poses
/// lean on the wheels they are compared with: a recording's 0.35 s delay read as 0.12 s.
PoseSeries scanOnlyPoses(const Dataset& dataset, const ScanPoints& points,
                         const MatchTrajectoryOptions& options, const MatchTrajectory& run);

/// Whether `method` de-skews with the wheels' odometry or the gyro read at the beams' stamps:
/// such a de-skew is corrupted by the very delay the clock sync measures, which is therefore
/// measured on the scans as measured (docs/calibration.md "Clock sync").
bool deskewReadsClocks(algo::DeskewMethod method);

/// The sensor agreement of `scan_poses` (one piece: scanOnlyPoses) with the dataset's wheels,
/// gyro and odometry topic.
algo::SensorAgreement scanAgreement(const Dataset& dataset, const PoseSeries& scan_poses);

/// The agreement the clock sync measures its first delay on: `matched` (of the scans matched
/// alone with `deskew`), or, where `deskew` reads the clocks being compared
/// (deskewReadsClocks), that of the scans matched alone as measured. What match, deskew and
/// twin start their sync from (calibrate makes its own motion as measured).
algo::SensorAgreement syncStartAgreement(const Dataset& dataset,
                                         const algo::SensorAgreement& matched,
                                         const std::string& deskew, bool stamp_is_last_beam);

/// `deskew --sync auto`: the scans matched alone (`deskew`, the default matcher, scanOnlyPoses)
/// and, where they lag the wheels, the wheels and the gyro moved onto the scans' clock as
/// calibrate and match do (algo::syncOntoScanClock, calibrate's thresholds). Returns the total
/// shift (0: none).
double syncOntoScans(Dataset& dataset, const std::string& deskew, bool stamp_is_last_beam);
/// The same from `first`, the sensor agreement of the scans matched alone with `deskew`
/// (syncStartAgreement applies).
double syncOntoScans(Dataset& dataset, const algo::SensorAgreement& first,
                     const std::string& deskew, bool stamp_is_last_beam);

}  // namespace slamprep::eval
