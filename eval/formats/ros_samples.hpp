#pragma once
// ROS 2 messages as slamprep values, with the checks an importer needs: finite fields, sane
// scan geometry, the wheel joints of a JointState.

#include <string>

#include "slamprep/core/laser_scan.hpp"
#include "slamprep/core/samples.hpp"
#include "slamprep/core/se2.hpp"
#include "slamprep/eval/formats/ros2_messages.hpp"

namespace slamprep::eval {

/// The scan of a LaserScan; InputError(where, field) on non-finite or inconsistent fields or an
/// empty scan. Ranges that are not finite become +inf (no return).
LaserScan scanFromMsg(const LaserScanMsg& m, const std::string& where);

/// The planar pose (x, y, yaw) of an Odometry; InputError on non-finite values or a zero
/// quaternion.
SE2 poseFromMsg(const OdometryMsg& m, const std::string& where);

/// Yaw rate and planar acceleration of an Imu; InputError on non-finite values.
ImuSample imuFromMsg(const ImuMsg& m, const std::string& where);

/// Which entries of a JointState are the left and right wheels: the joints named `left` and
/// `right` when given, else the one name containing "left" and the one containing "right".
/// InputError listing the joints found when there is no such joint or several.
struct WheelJoints {
  std::size_t left = 0, right = 0;
};
WheelJoints wheelJoints(const JointStateMsg& m, const std::string& left, const std::string& right,
                        const std::string& where);

}  // namespace slamprep::eval
