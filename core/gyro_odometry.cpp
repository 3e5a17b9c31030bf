#include "slamprep/core/gyro_odometry.hpp"

#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"

namespace slamprep {

double gyroHeadingAt(const HeadingSeries& heading, const ImuLog& imu, double t_s) {
  if (t_s < heading.frontStamp()) return (t_s - heading.frontStamp()) * imu.front().gyro_z_radps;
  if (t_s > heading.backStamp())
    return heading[heading.size() - 1].value +
           (t_s - heading.backStamp()) * imu.back().gyro_z_radps;
  return *heading.at(t_s);
}

PoseSeries integrateEncodersGyroHeading(const EncoderLog& encoders, const ImuLog& imu,
                                        const DiffDriveParams& geometry, int ticks_per_revolution,
                                        const SE2& T_odom_base0) {
  PoseSeries odometry;
  if (encoders.empty()) return odometry;
  if (imu.empty()) throw InputError("imu.csv", "no IMU samples: the heading cannot be the gyro's");
  const HeadingSeries heading = gyroHeading(imu);
  const double rad_per_tick = radiansPerTick(ticks_per_revolution);
  SE2 T_odom_base = T_odom_base0;
  double yaw_prev = gyroHeadingAt(heading, imu, encoders.front().stamp_s);
  odometry.push_back(encoders.front().stamp_s, T_odom_base);
  for (std::size_t k = 1; k < encoders.size(); ++k) {
    const EncoderSample &prev = encoders[k - 1], &cur = encoders[k];
    const double distance_m = geometry
                                  .twist((cur.ticks_left - prev.ticks_left) * rad_per_tick,
                                         (cur.ticks_right - prev.ticks_right) * rad_per_tick)
                                  .x();
    const double yaw = gyroHeadingAt(heading, imu, cur.stamp_s);
    // Eq. (1): T_k = T_(k-1) exp(s_k, 0, psi(t_k) - psi(t_(k-1))).
    T_odom_base = T_odom_base * SE2::exp({distance_m, 0.0, yaw - yaw_prev});
    yaw_prev = yaw;
    odometry.push_back(cur.stamp_s, T_odom_base);
  }
  return odometry;
}

}  // namespace slamprep
