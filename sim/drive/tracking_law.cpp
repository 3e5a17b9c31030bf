#include "slamprep/sim/drive/tracking_law.hpp"

#include <cmath>

namespace slamprep::sim {

Eigen::Vector2d trackingTwist(const SE2& T_world_base, const SE2& T_world_reference,
                              const Eigen::Vector2d& reference_twist, const TrackingParams& gains) {
  const SE2 e = between(T_world_base, T_world_reference);  // the error in the robot's frame
  const double v_r = reference_twist.x(), w_r = reference_twist.y();
  const double v = v_r * std::cos(e.yaw) + gains.k_x_per_s * e.x;  // Eq. (1)
  const double w = w_r + v_r * gains.k_y_per_m2 * e.y +
                   std::abs(v_r) * gains.k_theta_per_m * std::sin(e.yaw);  // Eq. (2)
  return {v, w};
}

Eigen::Vector2d capWheelRates(const Eigen::Vector2d& rates, double max_radps) {
  const double peak = rates.cwiseAbs().maxCoeff();
  return peak > max_radps ? Eigen::Vector2d(rates * (max_radps / peak)) : rates;
}

}  // namespace slamprep::sim
