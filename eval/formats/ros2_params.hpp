#pragma once
// `slamprep calibrate --ros2-params FILE` (docs/calibration.md, "ROS 2 parameters"): a calibration
// as ros2_control diff_drive_controller parameters plus the base_link -> laser static transform,
// in one ROS 2 parameter YAML file.

#include <string>

#include "slamprep/core/diff_drive.hpp"
#include "slamprep/core/se2.hpp"

namespace slamprep::eval {

struct Ros2ParamsInput {
  DiffDriveParams nominal;     ///< what the controller is configured with
  DiffDriveParams calibrated;  ///< the calibration's estimate
  SE2 T_base_lidar;            ///< the mount: calibrated (joint, ceres) or the dataset's
  std::string method;          ///< the calibration method, for the header comment
  bool mount_calibrated = false;
  bool relative_to_odometry = false;  ///< a log without ticks: only the multipliers mean anything
};

/// The YAML text: `diff_drive_controller: ros__parameters:` with wheel_separation and
/// wheel_radius (nominal b and mean nominal radius) and the three multipliers (calibrated over
/// nominal), then `base_link_to_laser: ros__parameters:` with frame_id, child_frame_id, x, y, z,
/// roll, pitch, yaw and `arguments`, the tf2_ros static_transform_publisher argument list.
std::string formatRos2Params(const Ros2ParamsInput& in);

}  // namespace slamprep::eval
