#pragma once
// Calibration error per parameter against the simulator's truth (docs/metrics.md).

#include <optional>
#include <string>
#include <vector>

#include "slamprep/core/diff_drive.hpp"
#include "slamprep/core/se2.hpp"

namespace slamprep::eval {

/// What a calibration produced, with 1-sigma uncertainties where the method gives them (square
/// roots of the covariance diagonal).
struct CalibrationEstimate {
  DiffDriveParams geometry;
  std::optional<Eigen::Vector3d> geometry_sigma;  ///< 1-sigma of (r_L, r_R, b) in m
  std::optional<SE2> T_base_lidar;                ///< lidar mount, if the method estimates it
  std::optional<Eigen::Vector3d> mount_sigma;     ///< 1-sigma of (x m, y m, yaw rad)
};

/// One parameter: estimate, truth and error in the parameter's report unit.
struct ParameterError {
  std::string name;       ///< "r_L", "r_R", "b", "mount_x", "mount_y", "mount_yaw"
  std::string unit;       ///< unit of `error` and `sigma`: "relative", "mm" or "deg"
  double estimate = 0.0;  ///< in SI (m, rad)
  double truth = 0.0;     ///< in SI (m, rad)
  /// r_L, r_R, b: (estimate - truth) / truth; x, y: (estimate - truth) in mm; yaw: the wrapped
  /// difference in degrees.
  double error = 0.0;
  std::optional<double> sigma;         ///< 1-sigma in `unit` (relative: sigma_m / truth)
  std::optional<bool> within_3_sigma;  ///< |error| <= 3 sigma, when sigma is known
};

struct CalibrationErrorResult {
  bool ok = false;
  std::string reason;
  std::vector<ParameterError> parameters;  ///< r_L, r_R, b, then the mount when estimated
  /// True when every parameter with a sigma has the truth inside +-3 sigma; nullopt if no sigma.
  std::optional<bool> all_within_3_sigma;
};

/// Refuses non-positive or non-finite true geometry, non-finite estimates and negative or
/// non-finite sigmas; the mount is compared only when both estimate and truth have one.
CalibrationErrorResult calibrationError(const CalibrationEstimate& estimate,
                                        const DiffDriveParams& true_geometry,
                                        const std::optional<SE2>& true_T_base_lidar = {});

}  // namespace slamprep::eval
