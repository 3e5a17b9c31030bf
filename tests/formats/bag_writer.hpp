#pragma once
// Bags made in code for the import tests: McapWriter plus the ROS 2 messages of
// ros2_messages.hpp, and a small robot bag (JointState or Odometry, LaserScan, /tf, /tf_static)
// whose lidar mount is given as tf transforms.

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "slamprep/eval/formats/mcap.hpp"
#include "slamprep/eval/formats/ros2_messages.hpp"

namespace slamprep::test {

/// Channels are added (with their schema) the first time a topic is used.
class TestBag {
 public:
  explicit TestBag(eval::McapWriterParams params = {}) : writer_(params) {}

  template <typename Msg>
  void add(const std::string& topic, std::string_view type, double stamp_s, const Msg& msg) {
    auto it = channels_.find(topic);
    if (it == channels_.end()) {
      auto schema = schemas_.find(std::string(type));
      if (schema == schemas_.end())
        schema = schemas_
                     .emplace(std::string(type), writer_.addSchema(std::string(type), "ros2msg",
                                                                   eval::ros2MsgSchema(type)))
                     .first;
      it = channels_.emplace(topic, writer_.addChannel(schema->second, topic, "cdr")).first;
    }
    const auto ns = static_cast<std::uint64_t>(std::llround(stamp_s * 1e9));
    writer_.addMessage(it->second, ns, ns, eval::encodeCdr(msg));
  }
  eval::McapWriter& writer() { return writer_; }
  std::string finish() { return writer_.finish(); }

 private:
  eval::McapWriter writer_;
  std::map<std::string, std::uint16_t> schemas_, channels_;
};

inline eval::RosHeader header(double stamp_s, const std::string& frame) {
  return {eval::rosTimeFromSeconds(stamp_s, "test"), frame};
}

/// parent -> child as a TransformStamped (T_parent_child).
inline eval::TransformStampedMsg transform(const std::string& parent, const std::string& child,
                                           const Eigen::Isometry3d& T, double stamp_s = 10.0) {
  eval::TransformStampedMsg t;
  t.header = header(stamp_s, parent);
  t.child_frame_id = child;
  t.translation = {T.translation().x(), T.translation().y(), T.translation().z()};
  const Eigen::Quaterniond q(T.linear());
  t.rotation = {q.x(), q.y(), q.z(), q.w()};
  return t;
}

/// Translation, then rotations about z, y, x (yaw, pitch, roll), as tf's RPY.
inline Eigen::Isometry3d pose3(double x, double y, double z, double roll, double pitch,
                               double yaw) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = Eigen::Vector3d(x, y, z);
  T.linear() = (Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) *
                Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX()))
                   .toRotationMatrix();
  return T;
}

struct RobotBagParams {
  std::vector<eval::TransformStampedMsg> tf_static;  ///< one /tf_static message at 10 s
  std::vector<eval::TransformStampedMsg> tf;         ///< on /tf at every odometry sample, with odom
  std::string laser_frame = "laser";
  std::vector<std::string> joints = {"wheel_left_joint", "wheel_right_joint"};
  bool joint_states = true;  ///< else only Odometry
  float time_increment_s = 1e-3f;
  /// Non-empty: /imu at every odometry sample in this frame, gyro (0.1, 0.2, 0.3) rad/s and
  /// accelerometer (1, 2, 9.8) m/s^2 in the IMU's axes.
  std::string imu_frame;
};

/// Beam ranges of the robot bag's scans: 1 + 0.25 i metres.
inline double testRange(std::size_t i) {
  return 1.0 + 0.25 * double(i);
}

/// 1 s of a robot driving at 0.2 m/s from 10 s: JointState (left 1 rad/s, right 3 rad/s) or
/// Odometry at 50 Hz, /tf odom -> base_link at the same times, 3 scans of 8 beams.
inline std::string robotBag(const RobotBagParams& p) {
  TestBag bag;
  for (int k = 0; k <= 50; ++k) {
    const double t = 10.0 + 0.02 * k;
    if (p.joint_states) {
      eval::JointStateMsg j;
      j.header = header(t, "base_link");
      j.name = p.joints;
      j.position = {1.0 * (t - 10.0), 3.0 * (t - 10.0)};
      bag.add("/joint_states", eval::kJointStateType, t, j);
    }
    eval::OdometryMsg o;
    o.header = header(t, "odom");
    o.child_frame_id = "base_link";
    o.position = {0.2 * (t - 10.0), 0.0, 0.0};
    bag.add("/odom", eval::kOdometryType, t, o);
    eval::TfMsg tf{{transform("odom", "base_link", pose3(0.2 * (t - 10.0), 0, 0, 0, 0, 0), t)}};
    for (auto d : p.tf) {
      d.header.stamp = eval::rosTimeFromSeconds(t, "test");
      tf.transforms.push_back(d);
    }
    bag.add("/tf", eval::kTfType, t, tf);
    if (!p.imu_frame.empty()) {
      eval::ImuMsg imu;
      imu.header = header(t, p.imu_frame);
      imu.angular_velocity = {0.1, 0.2, 0.3};
      imu.linear_acceleration = {1.0, 2.0, 9.8};
      bag.add("/imu", eval::kImuType, t, imu);
    }
    if (k == 0 && !p.tf_static.empty())
      bag.add("/tf_static", eval::kTfType, t, eval::TfMsg{p.tf_static});
  }
  for (int s = 0; s < 3; ++s) {
    const double t = 10.2 + 0.3 * s;
    eval::LaserScanMsg m;
    m.header = header(t, p.laser_frame);
    m.angle_min = -1.0f;
    m.angle_increment = 0.25f;
    m.angle_max = m.angle_min + 7 * m.angle_increment;
    m.time_increment = p.time_increment_s;
    m.scan_time = 0.3f;
    m.range_min = 0.1f;
    m.range_max = 20.0f;
    for (std::size_t i = 0; i < 8; ++i) m.ranges.push_back(float(testRange(i)));
    bag.add("/scan", eval::kLaserScanType, t + 0.01, m);
  }
  return bag.finish();
}

}  // namespace slamprep::test
