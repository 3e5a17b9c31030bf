#include "core/gyro_odometry.hpp"

#include "core/error.hpp"
#include "core/odometry.hpp"

namespace slamprep {

GyroYaw::GyroYaw(const ImuLog& imu) : imu_(imu) {
  if (imu_.empty()) throw InputError("imu.csv", "no IMU samples: the heading cannot be the gyro's");
}

double GyroYaw::at(double t_s) {
  // Advance the cursor over the whole intervals before t_s, adding their trapezoids.
  while (next_ < imu_.size() && imu_[next_].stamp_s <= t_s) {
    const ImuSample &a = imu_[next_ - 1], &b = imu_[next_];
    integral_ += 0.5 * (b.stamp_s - a.stamp_s) * (a.gyro_z_radps + b.gyro_z_radps);
    ++next_;
  }
  const ImuSample& a = imu_[next_ - 1];
  if (next_ == imu_.size() || t_s <= a.stamp_s)  // outside the samples: the rate held
    return integral_ + (t_s - a.stamp_s) * a.gyro_z_radps;
  const ImuSample& b = imu_[next_];
  const double f = (t_s - a.stamp_s) / (b.stamp_s - a.stamp_s);
  const double rate = a.gyro_z_radps + f * (b.gyro_z_radps - a.gyro_z_radps);
  return integral_ + 0.5 * (t_s - a.stamp_s) * (a.gyro_z_radps + rate);
}

PoseSeries integrateEncodersGyroHeading(const EncoderLog& encoders, const ImuLog& imu,
                                        const DiffDriveParams& geometry, int ticks_per_revolution,
                                        const SE2& T_odom_base0) {
  PoseSeries odometry;
  if (encoders.empty()) return odometry;
  GyroYaw gyro(imu);
  const double rad_per_tick = radiansPerTick(ticks_per_revolution);
  SE2 T_odom_base = T_odom_base0;
  double yaw_prev = gyro.at(encoders.front().stamp_s);
  odometry.push_back(encoders.front().stamp_s, T_odom_base);
  for (std::size_t k = 1; k < encoders.size(); ++k) {
    const EncoderSample &prev = encoders[k - 1], &cur = encoders[k];
    const double distance_m = geometry
                                  .twist((cur.ticks_left - prev.ticks_left) * rad_per_tick,
                                         (cur.ticks_right - prev.ticks_right) * rad_per_tick)
                                  .x();
    const double yaw = gyro.at(cur.stamp_s);
    // Eq. (1): T_k = T_(k-1) exp(s_k, 0, psi(t_k) - psi(t_(k-1))).
    T_odom_base = T_odom_base * SE2::exp({distance_m, 0.0, yaw - yaw_prev});
    yaw_prev = yaw;
    odometry.push_back(cur.stamp_s, T_odom_base);
  }
  return odometry;
}

}  // namespace slamprep
