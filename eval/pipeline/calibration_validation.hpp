#pragma once
// `calibrate --validate-fraction F` (docs/calibration.md, "Held-out validation"): calibrate on
// the first 1 - F of a recording's scans and score the raw and the calibrated odometry on the
// last F against the scan-to-map matched trajectory of those scans.

#include <string>
#include <vector>

#include "slamprep/algo/calibration/calibrate.hpp"
#include "slamprep/algo/calibration/calibration_report.hpp"
#include "slamprep/core/dataset.hpp"
#include "slamprep/eval/formats/wheel_odometry.hpp"

namespace slamprep::eval {

/// A recording cut by scan time. Only the scans are cut: intervals and matches are made between
/// scans, and the other streams (encoders, odometry, IMU, truth) stay whole so that de-skew and
/// the odometry guesses see the same data in both parts.
struct ValidationSplit {
  Dataset calibration;  ///< the scans before t_split_s
  Dataset held_out;     ///< the scans from t_split_s on
  double t_split_s = 0.0;
};

/// t_split = t_first + (1 - fraction) (t_last - t_first) over the scan stamps. Throws
/// InputError(source, ...) when fraction is not in (0, 1) or either part has fewer than 3 scans.
ValidationSplit splitForValidation(const Dataset& dataset, double fraction,
                                   const std::string& source);

struct HeldOutParams {
  double window_s = 10.0;           ///< relative pose error over this span (Eq. 1 of the docs)
  bool stamp_is_last_beam = false;  ///< the scans' stamps mark their last beam
};

/// The held-out part as every geometry is scored on it: the matched lidar poses of the scans
/// the matcher placed (fallbacks left out: their pose is the nominal odometry's guess), and the
/// recording's encoders to integrate.
struct HeldOutPart {
  std::vector<double> stamps_s;    ///< first-beam time of each kept scan
  std::vector<SE2> T_world_lidar;  ///< its scan-to-map matched pose
  OdometryEncoders odometry;       ///< the whole recording's (derived ones without ticks)
  HeldOutParams params;
  std::size_t scans = 0;  ///< held-out scans tracked
};

/// Tracks the held-out scans against a local map (eval::matchTrajectory, as `slamprep match`:
/// VICP de-skew unless the scans are instantaneous).
HeldOutPart heldOutPart(const Dataset& held_out, const OdometryEncoders& odometry,
                        const HeldOutParams& params = {});

/// Relative pose error of the encoders integrated with `geometry`, as lidar poses with mount
/// `T_base_lidar`, against the matched poses: every kept scan i starts a window, its end j is
/// the scan nearest to t_i + window_s (starts whose window runs past the part's end are left
/// out; one window over the whole part when it is shorter), E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j);
/// the mean of |t(E)| and of |yaw(E)|.
algo::HeldOutError heldOutError(const HeldOutPart& part, const DiffDriveParams& geometry,
                                const SE2& T_base_lidar);

/// The nominal geometry's error `raw` beside a method's run on `part`: its wheels with its own
/// mount where it estimates one (else the dataset's), and then also with the dataset's mount,
/// which tells a wrong mount from wrong wheels.
algo::ValidationFigures validationFigures(const HeldOutPart& part, const algo::HeldOutError& raw,
                                          const algo::CalibrationRun& run, const SE2& dataset_mount,
                                          double fraction);

}  // namespace slamprep::eval
