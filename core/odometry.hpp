#pragma once
// Wheel odometry: integrating encoder ticks with a wheel geometry.

#include <optional>

#include "slamprep/core/diff_drive.hpp"
#include "slamprep/core/samples.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep {

/// Wheel rotation (rad) per encoder tick.
double radiansPerTick(int ticks_per_revolution);

/// Body motion over one step from wheel rotation increments (rad), assuming constant wheel
/// rates over the step: the exact arc exp((v dt, 0, w dt)).
SE2 wheelIncrement(const DiffDriveParams& geometry, double dphi_left_rad, double dphi_right_rad);

/// Dead-reckoned T_odom_base at every encoder stamp, starting at `T_odom_base0`.
PoseSeries integrateEncoders(const EncoderLog& encoders, const DiffDriveParams& geometry,
                             int ticks_per_revolution, const SE2& T_odom_base0 = SE2());

/// T_world_odom that starts `odometry` on the true pose at its first stamp t0, so that it can be
/// compared with the truth without alignment (evo's --align_origin):
/// T_world_odom = T_world_base(t0) * T_odom_base(t0)^-1. nullopt when either series is empty or
/// the truth does not cover t0.
std::optional<SE2> anchorOnTruth(const PoseSeries& odometry, const PoseSeries& truth);

/// Every pose of `odometry` in the world frame: T_world_base = T_world_odom * T_odom_base.
PoseSeries inWorld(const PoseSeries& odometry, const SE2& T_world_odom);

}  // namespace slamprep
