#pragma once
// Odometry whose heading comes from the integrated gyro and whose translation comes from the
// wheels, as robots publish it when their heading is the IMU's (TurtleBot3's turtlebot3_node
// with use_imu).

#include "core/diff_drive.hpp"
#include "core/samples.hpp"
#include "core/time_series.hpp"

namespace slamprep {

/// The gyro's yaw rate integrated over time: trapezoids between samples, the rate linearly
/// interpolated inside a sample interval and held constant before the first and after the last
/// sample. Queries must not go back in time (the cursor only moves forward).
class GyroYaw {
 public:
  explicit GyroYaw(const ImuLog& imu);
  /// Integral of gyro_z from the first IMU stamp to t_s (rad; negative before it).
  double at(double t_s);

 private:
  const ImuLog& imu_;
  std::size_t next_ = 1;   ///< first sample after the interval the cursor is in
  double integral_ = 0.0;  ///< integral up to imu_[next_ - 1]
};

/// T_odom_base at every encoder stamp: heading yaw_0 + integral of gyro_z from the first encoder
/// stamp (GyroYaw), translation the wheels' distance (r_L dphi_L + r_R dphi_R) / 2 per encoder
/// step, along the arc whose turn is the gyro's over that step (Eq. (1) of docs/simulate.md,
/// "Odometry heading"). Throws InputError("imu.csv", ...) without IMU samples.
PoseSeries integrateEncodersGyroHeading(const EncoderLog& encoders, const ImuLog& imu,
                                        const DiffDriveParams& geometry, int ticks_per_revolution,
                                        const SE2& T_odom_base0 = SE2());

}  // namespace slamprep
