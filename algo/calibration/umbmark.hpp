#pragma once
// UMBmark (J. Borenstein, L. Feng, "Measurement and correction of systematic odometry errors in
// mobile robots", IEEE T-RA 12(6), 1996): drive an L x L square clockwise and counter-clockwise
// under odometry control, measure where the robot really ends, and correct the wheel-diameter
// ratio (E_d) and the wheel base (E_b). The classical baseline. Its step is first order in the
// errors; with the runs' encoder steps it is iterated to the geometry whose re-integrated
// odometry reproduces the return positions (docs/calibration.md: the bound, the iteration).

#include <Eigen/Core>
#include <vector>

#include "slamprep/algo/calibration/calibration_result.hpp"
#include "slamprep/algo/calibration/motion_model.hpp"

namespace slamprep::algo {

/// One square run: start and end poses as odometry computed them and as they really were.
struct UmbmarkRun {
  bool clockwise = false;
  SE2 T_world_start_odom;  ///< odometry pose at the start
  SE2 T_world_end_odom;    ///< odometry pose at the end
  SE2 T_world_start_true;  ///< reference (truth) pose at the start
  SE2 T_world_end_true;    ///< reference (truth) pose at the end
  /// The encoder steps from start to end. With them the correction is iterated (the odometry is
  /// re-integrated with each corrected geometry); without them only the paper's single step runs.
  std::vector<EncoderStep> steps;
};

struct UmbmarkParams {
  /// Side L of the square; the default is that of the shipped squares
  /// (worlds/scenarios/umbmark_cw.yaml, umbmark_ccw.yaml), as `calibrate --side` and bench use it.
  double side_m = 2.5;
  /// Geometry the odometry used during the runs; the corrections are applied to it.
  DiffDriveParams nominal;
  /// With every run's encoder steps: correct again until no parameter changes by more than this
  /// (relative) ...
  double tolerance = 1e-9;
  /// ... within this many corrections (the first is the paper's; 1: only it); otherwise refuse.
  int max_iterations = 50;
};

/// alpha, beta and the return errors are those of the recorded odometry (what the paper measures);
/// E_d, E_b and `geometry` are the whole correction of the nominal geometry. `iterations`: the
/// corrections applied (1: the paper's single step).
struct UmbmarkResult : CalibrationResult {
  double alpha_rad = 0.0;  ///< turn error per 90-degree turn (type A: wheel base)
  double beta_rad = 0.0;   ///< heading error per leg (type B: unequal diameters)
  double E_d = 1.0;        ///< (D_R / D_L) / (D_R / D_L)_nominal
  double E_b = 1.0;        ///< b_actual / b_nominal
  Eigen::Vector2d cg_cw = Eigen::Vector2d::Zero();   ///< mean return error, cw runs (start frame)
  Eigen::Vector2d cg_ccw = Eigen::Vector2d::Zero();  ///< mean return error, ccw runs
  DiffDriveParams first_order;                       ///< the paper's single-step geometry
};

/// Return-position error of one run in its start frame: true minus odometry.
Eigen::Vector2d umbmarkReturnError(const UmbmarkRun& run);

/// alpha, beta from the centres of gravity (x and y versions averaged), then E_d, E_b and the
/// corrected r_L, r_R, b. When every run has its encoder steps, the correction is iterated: the
/// steps are re-integrated with the corrected geometry, the return errors recomputed and corrected
/// again until the update is below `tolerance`; refuses when that does not converge. Covariance
/// from the scatter of the runs (needs >= 2 per direction; otherwise left empty).
UmbmarkResult calibrateUmbmark(const std::vector<UmbmarkRun>& runs, const UmbmarkParams& params);

/// The same from given centres of gravity (exposed for tests).
UmbmarkResult umbmarkFromErrors(const Eigen::Vector2d& cg_cw, const Eigen::Vector2d& cg_ccw,
                                const UmbmarkParams& params);

}  // namespace slamprep::algo
