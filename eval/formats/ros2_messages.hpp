#pragma once
// The ROS 2 messages slamprep exports and imports, as plain structs with their CDR encoding and
// their ros2msg schema text (the message definition followed by every message it uses, each
// introduced by a line of 80 '=' and "MSG: pkg/Type", as rosbag2 stores them in MCAP).

#include <array>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace slamprep::eval {

/// builtin_interfaces/msg/Time.
struct RosTime {
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;

  /// Nanoseconds since the epoch of the clock (may be negative).
  std::int64_t nanoseconds() const { return std::int64_t{sec} * 1000000000 + nanosec; }
  double seconds() const { return sec + nanosec * 1e-9; }
};

/// The ROS time nearest to `stamp_s` (rounded to the nanosecond). Throws InputError naming
/// `where` when the stamp is not finite or outside the int32 seconds range.
RosTime rosTimeFromSeconds(double stamp_s, const std::string& where);
RosTime rosTimeFromNanoseconds(std::int64_t ns);

/// std_msgs/msg/Header.
struct RosHeader {
  RosTime stamp;
  std::string frame_id;
};

/// sensor_msgs/msg/LaserScan.
struct LaserScanMsg {
  RosHeader header;
  float angle_min = 0, angle_max = 0, angle_increment = 0, time_increment = 0, scan_time = 0;
  float range_min = 0, range_max = 0;
  std::vector<float> ranges;
  std::vector<float> intensities;
};

/// geometry_msgs/msg/Quaternion (x, y, z, w) of a yaw about z.
struct Quaternion {
  double x = 0, y = 0, z = 0, w = 1;
};
Quaternion quaternionFromYaw(double yaw_rad);

/// nav_msgs/msg/Odometry.
struct OdometryMsg {
  RosHeader header;
  std::string child_frame_id;
  std::array<double, 3> position{};
  Quaternion orientation;
  std::array<double, 36> pose_covariance{};
  std::array<double, 3> linear{};   ///< twist.twist.linear, in child_frame_id
  std::array<double, 3> angular{};  ///< twist.twist.angular
  std::array<double, 36> twist_covariance{};
};

/// sensor_msgs/msg/Imu.
struct ImuMsg {
  RosHeader header;
  Quaternion orientation;
  std::array<double, 9> orientation_covariance{};
  std::array<double, 3> angular_velocity{};
  std::array<double, 9> angular_velocity_covariance{};
  std::array<double, 3> linear_acceleration{};
  std::array<double, 9> linear_acceleration_covariance{};
};

/// sensor_msgs/msg/JointState.
struct JointStateMsg {
  RosHeader header;
  std::vector<std::string> name;
  std::vector<double> position;
  std::vector<double> velocity;
  std::vector<double> effort;
};

/// geometry_msgs/msg/TransformStamped.
struct TransformStampedMsg {
  RosHeader header;
  std::string child_frame_id;
  std::array<double, 3> translation{};
  Quaternion rotation;
};

/// tf2_msgs/msg/TFMessage.
struct TfMsg {
  std::vector<TransformStampedMsg> transforms;
};

// Schema names as ROS 2 spells them.
inline constexpr std::string_view kLaserScanType = "sensor_msgs/msg/LaserScan";
inline constexpr std::string_view kOdometryType = "nav_msgs/msg/Odometry";
inline constexpr std::string_view kImuType = "sensor_msgs/msg/Imu";
inline constexpr std::string_view kJointStateType = "sensor_msgs/msg/JointState";
inline constexpr std::string_view kTfType = "tf2_msgs/msg/TFMessage";

/// The ros2msg schema text of one of the types above (empty for any other type).
std::string ros2MsgSchema(std::string_view type);

std::string encodeCdr(const LaserScanMsg& m);
std::string encodeCdr(const OdometryMsg& m);
std::string encodeCdr(const ImuMsg& m);
std::string encodeCdr(const JointStateMsg& m);
std::string encodeCdr(const TfMsg& m);

// Decoders throw InputError naming `where` and the field on truncated or malformed data.
LaserScanMsg decodeLaserScan(std::string_view cdr, const std::string& where);
OdometryMsg decodeOdometry(std::string_view cdr, const std::string& where);
ImuMsg decodeImu(std::string_view cdr, const std::string& where);
JointStateMsg decodeJointState(std::string_view cdr, const std::string& where);
TfMsg decodeTf(std::string_view cdr, const std::string& where);

}  // namespace slamprep::eval
