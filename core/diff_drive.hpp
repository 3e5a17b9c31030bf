#pragma once
// Differential-drive wheel geometry and kinematics (docs/design.md#differential-drive-kinematics).

#include <Eigen/Core>

namespace slamprep {

/// Wheel geometry: r_L, r_R and the wheel base b (distance between the wheel contact points).
struct DiffDriveParams {
  double radius_left_m = 0.1;   ///< r_L
  double radius_right_m = 0.1;  ///< r_R
  double wheel_base_m = 0.5;    ///< b

  /// J with (v, w) = J (w_L, w_R): J = [[r_L/2, r_R/2], [-r_L/b, r_R/b]].
  Eigen::Matrix2d jacobian() const {
    return (Eigen::Matrix2d() << radius_left_m / 2, radius_right_m / 2,
            -radius_left_m / wheel_base_m, radius_right_m / wheel_base_m)
        .finished();
  }

  /// Body twist (v m/s, w rad/s) from wheel rates (rad/s).
  Eigen::Vector2d twist(double wheel_rate_left_radps, double wheel_rate_right_radps) const {
    return jacobian() * Eigen::Vector2d(wheel_rate_left_radps, wheel_rate_right_radps);
  }

  /// Wheel rates (w_L, w_R) that produce the body twist (v, w).
  Eigen::Vector2d wheelRates(double v_mps, double w_radps) const {
    return {(v_mps - w_radps * wheel_base_m / 2) / radius_left_m,
            (v_mps + w_radps * wheel_base_m / 2) / radius_right_m};
  }
};

}  // namespace slamprep
