#pragma once
// The calibration pipeline on a dataset: the lidar motion the interval methods consume.

#include <string>
#include <vector>

#include "algo/calibration/calibration.hpp"
#include "algo/calibration/dataset_motion.hpp"
#include "core/dataset.hpp"

namespace slamprep::eval {

/// Where the lidar motion for calibration comes from.
struct CalibrationMotionOptions {
  bool from_icp = true;  ///< scan matching; false: ground truth (an oracle run)
  /// Match scans de-skewed with this method first. "auto": the gyro (imu) when the log has one,
  /// since it does not depend on the wheel geometry being calibrated (de-skewing with the wrong
  /// geometry biased the mount yaw by 0.12 deg on 3 minutes of driving; imu: 0.02 deg), else
  /// odom-linear. "none": raw scans, biased by the distortion itself.
  std::string deskew = "auto";
  algo::IntervalParams intervals;
};

struct CalibrationMotion {
  std::vector<algo::ScanMatch> matches;  ///< consecutive scans (none for ground truth)
  std::vector<PoseSeries> chains;        ///< T_world_lidar chains (one for ground truth)
  int failed_matches = 0;
  algo::IntervalSet intervals;
};

/// Lidar motion and intervals from a dataset (de-skew with the nominal geometry, as the robot
/// believes, then point-to-line ICP between consecutive scans; or ground truth).
CalibrationMotion calibrationMotion(const Dataset& dataset,
                                    const CalibrationMotionOptions& options);

}  // namespace slamprep::eval
