#pragma once
// Drift of a dead-reckoned trajectory against ground truth (docs/metrics.md, "Odometry drift").

#include <optional>
#include <string>

#include "slamprep/core/time_series.hpp"

namespace slamprep::eval {

struct DriftParams {
  double max_time_difference_s = 0.01;  ///< association tolerance, see associateByTime
};

struct DriftResult {
  bool ok = false;
  std::string reason;
  std::size_t matched = 0;    ///< odometry poses compared
  std::size_t unmatched = 0;  ///< odometry poses without ground truth close enough in time
  SE2 T_world_odom;           ///< start alignment Q_0 P_0^-1 (first compared pose)
  /// E_N = Q_N^-1 T_world_odom P_N at the last pose: the odometry in the true frame (its yaw is
  /// the signed heading error, odometry minus truth).
  SE2 final_error;
  double final_position_error_m = 0.0;   ///< |t(E_N)|
  double final_heading_error_deg = 0.0;  ///< |angle(E_N)|
  double max_position_error_m = 0.0;     ///< max over all compared poses
  double path_length_m = 0.0;            ///< ground-truth path length over the compared poses
  double duration_s = 0.0;               ///< last minus first compared stamp
};

/// Aligns the odometry's first pose onto the ground truth at the same stamp (no other fitting:
/// drift is what accumulates from there).
DriftResult odometryDrift(const PoseSeries& T_odom_base, const PoseSeries& T_world_base_true,
                          const DriftParams& params = {});

struct DriftComparison {
  bool ok = false;
  std::string reason;
  DriftResult nominal;     ///< odometry integrated with the nominal geometry
  DriftResult calibrated;  ///< odometry integrated with the calibrated geometry
  /// nominal / calibrated error (> 1: calibration helped); nullopt when the calibrated error is 0.
  std::optional<double> final_position_ratio;
  std::optional<double> final_heading_ratio;
  std::optional<double> max_position_ratio;
};

DriftComparison compareDrift(const PoseSeries& nominal, const PoseSeries& calibrated,
                             const PoseSeries& T_world_base_true, const DriftParams& params = {});

}  // namespace slamprep::eval
