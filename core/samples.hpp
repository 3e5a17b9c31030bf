#pragma once
// Raw proprioceptive sensor samples, as a robot logs them.

#include <cstdint>
#include <vector>

namespace slamprep {

/// Wheel encoders: cumulative ticks since start, left and right.
struct EncoderSample {
  double stamp_s = 0.0;
  std::int64_t ticks_left = 0;
  std::int64_t ticks_right = 0;
};

/// A planar IMU: yaw rate and the horizontal specific force in the base frame.
struct ImuSample {
  double stamp_s = 0.0;
  double gyro_z_radps = 0.0;
  double accel_x_mps2 = 0.0;
  double accel_y_mps2 = 0.0;
};

using EncoderLog = std::vector<EncoderSample>;
using ImuLog = std::vector<ImuSample>;

}  // namespace slamprep
