#pragma once
// Joint closed-form calibration of r_L, r_R, b and the lidar mount (x, y, yaw), after
// A. Censi, A. Franchi, L. Marchionni, G. Oriolo, "Simultaneous calibration of odometry and sensor
// parameters for mobile robots", IEEE T-RO 29(2), 2013.

#include <vector>

#include "slamprep/algo/calibration/calibration_result.hpp"

namespace slamprep::algo {

struct JointParams {
  /// Refuse when a least-squares step is worse conditioned than this (column-equilibrated).
  /// 1e3: well-excited drives score 2-20; a single-curvature circle scores 1e3-1e4 and
  /// gives 20 % errors there (measured in the default suite).
  double max_condition_number = 1e3;
  /// Refuse with fewer intervals than this (after trimming).
  int min_intervals = 8;
  /// Rounds of outlier trimming after the first fit.
  int trim_rounds = 3;
  /// Fraction of the remaining intervals dropped per round, worst normalised residual first.
  double trim_fraction = 0.01;
  /// Also estimate a sideslip k (s), the base moving sideways at k v w in turns
  /// (docs/calibration.md, "Sideslip"): one more linear unknown m = k b in stage 2.
  bool estimate_sideslip = false;
  /// Spans whose headings loop closures corrected (calibrate --loop-closure): stage 1's
  /// covariance propagates the correction (loop_covariance.hpp). Empty: intervals as matched.
  std::vector<LoopSpan> heading_loops;
};

struct JointResult : CalibrationResult {
  double J21 = 0.0;               ///< -r_L / b
  double J22 = 0.0;               ///< r_R / b
  double lambda = 0.0;            ///< Lagrange multiplier of the unit-circle constraint
  double sigma_theta_rad = 0.0;   ///< scan-match rotation noise, from the residuals
  double sigma_x_m = 0.0;         ///< scan-match translation noise along lidar x
  double sigma_y_m = 0.0;         ///< ... along lidar y
  std::vector<int> used;          ///< indices of the intervals in the final fit
  double sideslip_s = 0.0;        ///< estimated sideslip k (0 when not estimated)
  double sideslip_sigma_s = 0.0;  ///< its 1-sigma
};

/// Stage 1: J21, J22 by least squares on the rotations (fitRotation). Stage 2: b and the mount
/// from the 5x5 quadratic form under cos^2 + sin^2 = 1 (derivation in joint_censi.cpp). Then
/// rounds of trimming. Covariance (r_L, r_R, b, l_x, l_y, l_yaw): the inverse Fisher information
/// of each stage with the noise estimated from the residuals, stage 1 propagated into stage 2.
JointResult calibrateJoint(const std::vector<CalibrationInterval>& intervals,
                           const JointParams& params = {});

}  // namespace slamprep::algo
