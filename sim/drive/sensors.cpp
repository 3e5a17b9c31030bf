#include "slamprep/sim/drive/sensors.hpp"

#include <cmath>

#include "slamprep/core/odometry.hpp"

namespace slamprep::sim {

std::int64_t quantizeTicks(double wheel_angle_rad, int ticks_per_revolution) {
  return static_cast<std::int64_t>(
      std::floor(wheel_angle_rad / radiansPerTick(ticks_per_revolution)));
}

ImuSample Imu::sample(double stamp_s, double yaw_rate_radps,
                      const Eigen::Vector2d& accel_base_mps2) {
  ImuSample s;
  s.stamp_s = stamp_s;
  // Draw in a fixed order so each quantity's noise is reproducible.
  s.gyro_z_radps =
      yaw_rate_radps + config_.gyro_bias_radps + config_.gyro_noise_radps * rng_.gaussian();
  s.accel_x_mps2 =
      accel_base_mps2.x() + config_.accel_bias_x_mps2 + config_.accel_noise_mps2 * rng_.gaussian();
  s.accel_y_mps2 =
      accel_base_mps2.y() + config_.accel_bias_y_mps2 + config_.accel_noise_mps2 * rng_.gaussian();
  return s;
}

Eigen::Vector2d WheelSlip::count(const Eigen::Vector2d& turned_rad, double dt_s) {
  const double a = std::exp(-std::max(0.0, dt_s) / tau_s_);
  const double q = sigma_ * std::sqrt(1.0 - a * a);
  for (int i = 0; i < 2; ++i) s_[i] = a * s_[i] + q * rng_.gaussian();  // left first, then right
  counted_rad_ += turned_rad.cwiseProduct(Eigen::Vector2d::Ones() + s_);
  if (turn_sigma_ > 0.0) {  // drawn after s: a run without turn slip keeps its numbers
    u_ = a * u_ + turn_sigma_ * std::sqrt(1.0 - a * a) * rng_.gaussian();
    const double turning = 0.5 * (turned_rad.y() - turned_rad.x());
    counted_rad_ += Eigen::Vector2d(-u_ * turning, u_ * turning);
  }
  if (common_sigma_ > 0.0) {  // drawn last: runs without it keep their numbers
    c_ = a * c_ + common_sigma_ * std::sqrt(1.0 - a * a) * rng_.gaussian();
    const double rolling = 0.5 * (turned_rad.x() + turned_rad.y());  // the step's straight part
    counted_rad_ += Eigen::Vector2d::Constant(c_ * rolling);
  }
  return counted_rad_;
}

}  // namespace slamprep::sim
