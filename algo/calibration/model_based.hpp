#pragma once
// Model-based odometry calibration (the lecture; docs/design.md#calibration-model-based-method):
// J21, J22 from the rotations, then b from the translations, r_L = -J21 b, r_R = J22 b. The lidar
// is assumed at the robot centre.

#include <vector>

#include "slamprep/algo/calibration/calibration_result.hpp"

namespace slamprep::algo {

struct ModelBasedParams {
  /// Refuse when a least-squares step is worse conditioned than this (column-equilibrated).
  /// 1e3: well-excited drives score 2-20; a single-curvature circle scores 1e3-1e4 and
  /// gives 20 % errors there (measured in the default suite).
  double max_condition_number = 1e3;
  /// Refuse with fewer intervals than this.
  int min_intervals = 5;
};

struct ModelBasedResult : CalibrationResult {
  double J21 = 0.0;  ///< -r_L / b
  double J22 = 0.0;  ///< r_R / b
};

/// Two-stage least squares; covariance (r_L, r_R, b) from the residual noise of each stage with
/// the rotation stage's uncertainty propagated into b (twoStageCovariance).
ModelBasedResult calibrateModelBased(const std::vector<CalibrationInterval>& intervals,
                                     const ModelBasedParams& params = {});

}  // namespace slamprep::algo
