#pragma once
// Direct linear odometry calibration (the lecture; docs/design.md, "Calibration: direct linear
// method"): u*_i = X u_i with u_i the odometry increment from the nominal geometry and u*_i the
// measured one; X (3x3) by stacked least squares. General, simple, not very accurate.

#include <Eigen/Core>
#include <vector>

#include "slamprep/algo/calibration/calibration_result.hpp"

namespace slamprep::algo {

struct DirectLinearParams {
  /// Geometry the odometry increments u_i are integrated with (what the odometry is told).
  DiffDriveParams nominal;
  /// Refuse when the stacked design is worse conditioned than this (column-equilibrated).
  /// 1e3: well-excited drives score 2-20; a single-curvature circle scores 1e3-1e4 and
  /// gives 20 % errors there (measured in the default suite).
  double max_condition_number = 1e3;
  /// Refuse with fewer intervals than this.
  int min_intervals = 5;
};

struct DirectLinearResult : CalibrationResult {
  /// u* = X u, rows and columns ordered (x, y, theta).
  Eigen::Matrix3d X = Eigen::Matrix3d::Identity();
  /// 1-sigma of every entry of X.
  Eigen::Matrix3d X_sigma = Eigen::Matrix3d::Zero();
  /// What X implies for the twist: (ds*, dth*) = K (ds, dth), K = [[X11, X13], [X31, X33]]
  /// (small increments: u = (ds, ~0, dth)); then J_true = K J_nominal gives the geometry.
  Eigen::Matrix2d K = Eigen::Matrix2d::Identity();
};

/// Fits X and derives r_L = 2 J11, r_R = 2 J12 and 1/b by least squares on J21 = -r_L / b,
/// J22 = r_R / b from J = K J_nominal. Exact when the true geometry is the nominal one scaled
/// uniformly (then X = diag(s, s, 1)); otherwise a small-increment approximation. The lidar is
/// assumed at the centre. Covariance of (r_L, r_R, b) propagated from the rows of X.
DirectLinearResult calibrateDirectLinear(const std::vector<CalibrationInterval>& intervals,
                                         const DirectLinearParams& params);

/// The geometry J = K J_nominal implies (see DirectLinearResult::K).
DiffDriveParams geometryFromTwistMap(const Eigen::Matrix2d& K, const DiffDriveParams& nominal);

}  // namespace slamprep::algo
