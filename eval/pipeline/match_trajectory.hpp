#pragma once
// `slamprep match` on a dataset: scan-to-local-map lidar odometry (algo::trackKeyframes) guided
// by the dataset's odometry, its trajectory of the base, its per-scan lines and its summary
// (docs/matching.md).

#include <string>
#include <vector>

#include "slamprep/algo/matching/keyframe_odometry.hpp"
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
};

struct MatchTrajectory {
  algo::KeyframeOdometry tracked;
  std::vector<double> stamps_s;      ///< first-beam time of every scan
  PoseSeries T_world_base;           ///< the base at every scan's first beam (T_world_lidar l^-1)
  std::size_t odometry_guesses = 0;  ///< scans 1..n-1 with an odometry guess
  std::size_t gyro_guesses = 0;      ///< scans 1..n-1 with a gyro guess
  double seconds = 0.0;              ///< wall-clock time of the tracking
};

/// Every scan's points in its first-beam lidar frame: as measured, or (`vicp`) de-skewed by VICP
/// where it applies; a scan it refuses (e.g. time_increment 0) is kept as measured and counted
/// in `deskew_refused`. What `slamprep match` tracks.
std::vector<Points2> matchScanPoints(const Dataset& dataset, const std::string& deskew,
                                     bool stamp_is_last_beam, int* deskew_refused = nullptr);

/// Tracks the scans given as `points` (one per dataset scan, in its first-beam lidar frame; e.g.
/// the scans as measured or de-skewed). The guesses of scan k: the nominal odometry between the
/// two first beams (algo::odometryLidarMotion, as calibrate's matches use), the gyro's turn over
/// them, the last step and standing still (algo::trackKeyframes). The world frame is the odometry's
/// at the first scan (the origin without odometry). Throws InputError when first-beam times do not
/// increase.
MatchTrajectory matchTrajectory(const Dataset& dataset, const std::vector<Points2>& points,
                                const MatchTrajectoryOptions& options = {});

/// matches.jsonl (docs/matching.md): one object per scan after the first.
std::string formatTrackedMatches(const MatchTrajectory& run);

/// The poses of the scans whose match was accepted (a fallback's pose is a guess, not a
/// measurement).
PoseSeries acceptedPoses(const MatchTrajectory& run);

/// `deskew --sync auto`: the scans matched (`deskew`, the default matcher) and, where they lag
/// the wheels, the wheels and the gyro moved onto the scans' clock as calibrate and match do
/// (algo::syncOntoScanClock, calibrate's thresholds). Returns the total shift (0: none).
double syncOntoScans(Dataset& dataset, const std::string& deskew, bool stamp_is_last_beam);

}  // namespace slamprep::eval
