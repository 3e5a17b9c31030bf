#pragma once
// Odometry whose heading comes from the integrated gyro and whose translation comes from the
// wheels, as robots publish it when their heading is the IMU's (TurtleBot3's turtlebot3_node
// with use_imu).

#include "slamprep/core/diff_drive.hpp"
#include "slamprep/core/heading.hpp"
#include "slamprep/core/samples.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep {

/// psi(t): the gyro's heading (gyroHeading of `imu`) at t, linear between samples, and carried on
/// at the first or last sample's rate before or after them. `heading` = gyroHeading(imu).
double gyroHeadingAt(const HeadingSeries& heading, const ImuLog& imu, double t_s);

/// T_odom_base at every encoder stamp: heading yaw_0 + psi(t_k) - psi(t_0) (gyroHeadingAt),
/// translation the wheels' distance (r_L dphi_L + r_R dphi_R) / 2 per encoder step, along the
/// arc whose turn is the gyro's over that step (Eq. (1) of docs/simulate.md, "Odometry
/// heading"). Throws InputError("imu.csv", ...) without IMU samples.
PoseSeries integrateEncodersGyroHeading(const EncoderLog& encoders, const ImuLog& imu,
                                        const DiffDriveParams& geometry, int ticks_per_revolution,
                                        const SE2& T_odom_base0 = SE2());

}  // namespace slamprep
