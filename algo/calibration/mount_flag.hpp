#pragma once
// A calibrated lidar mount far from the one the recording gave (docs/calibration.md, "Flags").
// A tf or a --lidar-mount is measured on the robot to a centimetre; a calibration that puts the
// lidar decimetres away has absorbed something else into the mount (a clock lag, slip, a loose
// heading), or the recording does not pin the mount down, and its wheels are suspect with it.
// Seen on real Neatos: joint placed one lidar 264 mm beside its tf (1 sigma 7 mm), another
// 196 mm away with b 22 % under the nominal, and only their held-out scores showed it.

#include <optional>
#include <string>

#include "slamprep/algo/calibration/calibration_result.hpp"
#include "slamprep/algo/calibration/nominal_flags.hpp"
#include "slamprep/core/se2.hpp"

namespace slamprep::algo {

struct MountFlagParams {
  double max_offset_m = 0.05;  ///< a tf is rarely off by more; a few scan-matching errors are less
  double max_yaw_deg = 5.0;
  double sigmas = 3.0;  ///< beyond this many sigmas the estimate contradicts the given mount
};

/// A flag with param "lidar_mount" (ratio 1) where `result` estimates the mount and it lies
/// more than max_offset_m or max_yaw_deg from `given` (the mount the recording came with,
/// described by `given_from`, e.g. "tf base_link->laser"). The cause says by how much, and
/// whether the estimate's own sigma allows the given mount (a loose mount: keep the given one,
/// --lidar-mount dataset) or excludes it (a wrong tf, or an error of the wheels or clocks the
/// mount absorbed).
std::optional<NominalFlag> mountFlag(const CalibrationResult& result, const SE2& given,
                                     const std::string& given_from,
                                     const MountFlagParams& params = {});

}  // namespace slamprep::algo
