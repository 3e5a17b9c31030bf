#pragma once
// Wheel odometry: integrating encoder ticks with a wheel geometry.

#include "core/diff_drive.hpp"
#include "core/samples.hpp"
#include "core/time_series.hpp"

namespace slamprep {

/// Wheel rotation (rad) per encoder tick.
double radiansPerTick(int ticks_per_revolution);

/// Body motion over one step from wheel rotation increments (rad), assuming constant wheel
/// rates over the step: the exact arc exp((v dt, 0, w dt)).
SE2 wheelIncrement(const DiffDriveParams& geometry, double dphi_left_rad, double dphi_right_rad);

/// Dead-reckoned T_odom_base at every encoder stamp, starting at `T_odom_base0`.
PoseSeries integrateEncoders(const EncoderLog& encoders, const DiffDriveParams& geometry,
                             int ticks_per_revolution, const SE2& T_odom_base0 = SE2());

}  // namespace slamprep
