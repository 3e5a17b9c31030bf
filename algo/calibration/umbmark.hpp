#pragma once
// UMBmark (J. Borenstein, L. Feng, "Measurement and correction of systematic odometry errors in
// mobile robots", IEEE T-RA 12(6), 1996): drive an L x L square clockwise and counter-clockwise
// under odometry control, measure where the robot really ends, and correct the wheel-diameter
// ratio (E_d) and the wheel base (E_b). The classical baseline; first order in the errors.

#include <Eigen/Core>
#include <vector>

#include "algo/calibration/calibration_result.hpp"

namespace slamprep::algo {

/// One square run: start and end poses as odometry computed them and as they really were.
struct UmbmarkRun {
  bool clockwise = false;
  SE2 T_world_start_odom;  ///< odometry pose at the start
  SE2 T_world_end_odom;    ///< odometry pose at the end
  SE2 T_world_start_true;  ///< reference (truth) pose at the start
  SE2 T_world_end_true;    ///< reference (truth) pose at the end
};

struct UmbmarkParams {
  /// Side L of the square.
  double side_m = 4.0;
  /// Geometry the odometry used during the runs; the corrections are applied to it.
  DiffDriveParams nominal;
};

struct UmbmarkResult : CalibrationResult {
  double alpha_rad = 0.0;  ///< turn error per 90-degree turn (type A: wheel base)
  double beta_rad = 0.0;   ///< heading error per leg (type B: unequal diameters)
  double E_d = 1.0;        ///< D_R / D_L
  double E_b = 1.0;        ///< b_actual / b_nominal
  Eigen::Vector2d cg_cw = Eigen::Vector2d::Zero();   ///< mean return error, cw runs (start frame)
  Eigen::Vector2d cg_ccw = Eigen::Vector2d::Zero();  ///< mean return error, ccw runs
};

/// Return-position error of one run in its start frame: true minus odometry.
Eigen::Vector2d umbmarkReturnError(const UmbmarkRun& run);

/// alpha, beta from the centres of gravity (x and y versions averaged), then E_d, E_b and the
/// corrected r_L, r_R, b. Covariance from the scatter of the runs (needs >= 2 per direction;
/// otherwise left empty).
UmbmarkResult calibrateUmbmark(const std::vector<UmbmarkRun>& runs, const UmbmarkParams& params);

/// The same from given centres of gravity (exposed for tests).
UmbmarkResult umbmarkFromErrors(const Eigen::Vector2d& cg_cw, const Eigen::Vector2d& cg_ccw,
                                const UmbmarkParams& params);

}  // namespace slamprep::algo
