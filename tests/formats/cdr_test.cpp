// CDR encoding of the ROS 2 messages: byte layout, alignment, round trip, truncation.
#include "slamprep/eval/formats/cdr.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/ros2_messages.hpp"

namespace slamprep::eval {
namespace {

template <typename T>
T at(const std::string& bytes, std::size_t offset) {
  T v;
  std::memcpy(&v, bytes.data() + offset, sizeof(T));
  return v;
}

TEST(Cdr, AlignsEachPrimitiveToItsSizeAfterTheHeader) {
  CdrWriter w;
  w.u8(7);
  w.f64(1.5);  // pads 7 bytes: offset 8 counted from after the 4-byte header -> byte 12
  w.u8(1);
  w.u32(9);        // body offset 17 -> pad to 20 -> byte 24
  w.string("ab");  // length @28, "ab\0" @32..34
  w.f64(2.0);      // body offset 31 -> pad to 32 -> byte 36
  const std::string& b = w.bytes();
  ASSERT_EQ(b.size(), 44u);
  EXPECT_EQ(b.substr(0, 4), std::string("\0\1\0\0", 4));  // CDR_LE
  EXPECT_EQ(at<double>(b, 12), 1.5);
  EXPECT_EQ(at<std::uint32_t>(b, 24), 9u);
  EXPECT_EQ(at<std::uint32_t>(b, 28), 3u);  // length includes the NUL
  EXPECT_EQ(b.substr(32, 3), std::string("ab\0", 3));
  EXPECT_EQ(at<double>(b, 36), 2.0);
}

TEST(Cdr, OdometryLayoutMatchesTheRos2WireFormat) {
  OdometryMsg m;
  m.header = {{12, 500}, "odom"};
  m.child_frame_id = "base_link";
  m.position = {1, 2, 0};
  const std::string b = encodeCdr(m);
  // header: sec @4, nanosec @8, frame_id length @12, "odom\0" @16..20; child_frame_id length
  // aligned to 4 @24, "base_link\0" @28..37; position.x aligned to 8: body offset 34 -> 40 -> @44.
  EXPECT_EQ(at<std::int32_t>(b, 4), 12);
  EXPECT_EQ(at<std::uint32_t>(b, 8), 500u);
  EXPECT_EQ(at<std::uint32_t>(b, 12), 5u);
  EXPECT_EQ(at<std::uint32_t>(b, 24), 10u);
  EXPECT_EQ(at<double>(b, 44), 1.0);
  // 4 + 40 + 3 position + 4 orientation + 36 + 6 twist + 36 doubles.
  EXPECT_EQ(b.size(), 44u + (3 + 4 + 36 + 6 + 36) * 8);
}

TEST(Cdr, EveryMessageRoundTrips) {
  LaserScanMsg s;
  s.header = {{3, 999999999}, "laser"};
  s.angle_min = -1.5f;
  s.angle_max = 1.5f;
  s.angle_increment = 0.25f;
  s.time_increment = 1e-4f;
  s.scan_time = 0.1f;
  s.range_min = 0.1f;
  s.range_max = std::numeric_limits<float>::infinity();
  s.ranges = {1.f, std::numeric_limits<float>::infinity(), 3.f};
  const LaserScanMsg s2 = decodeLaserScan(encodeCdr(s), "s");
  EXPECT_EQ(s2.header.stamp.nanosec, 999999999u);
  EXPECT_EQ(s2.header.frame_id, "laser");
  EXPECT_EQ(s2.ranges, s.ranges);
  EXPECT_EQ(s2.range_max, s.range_max);
  EXPECT_TRUE(s2.intensities.empty());

  JointStateMsg j;
  j.header.frame_id = "";  // empty strings still carry their NUL
  j.name = {"wheel_left_joint", "r"};
  j.position = {1.25, -3.5};
  const JointStateMsg j2 = decodeJointState(encodeCdr(j), "j");
  EXPECT_EQ(j2.name, j.name);
  EXPECT_EQ(j2.position, j.position);

  TfMsg tf;
  tf.transforms.resize(2);
  tf.transforms[1].child_frame_id = "laser";
  tf.transforms[1].translation = {0.1, 0.2, 0};
  tf.transforms[1].rotation = quaternionFromYaw(0.5);
  const TfMsg tf2 = decodeTf(encodeCdr(tf), "tf");
  ASSERT_EQ(tf2.transforms.size(), 2u);
  EXPECT_EQ(tf2.transforms[1].child_frame_id, "laser");
  EXPECT_EQ(tf2.transforms[1].rotation.z, std::sin(0.25));

  ImuMsg imu;
  imu.angular_velocity = {0, 0, 0.7};
  imu.orientation_covariance[0] = -1;
  const ImuMsg imu2 = decodeImu(encodeCdr(imu), "imu");
  EXPECT_EQ(imu2.angular_velocity[2], 0.7);
  EXPECT_EQ(imu2.orientation_covariance[0], -1);
}

TEST(Cdr, BigEndianMessagesDecode) {
  // A JointState header written big endian by hand: sec = 1, nanosec = 2, frame "" (length 1).
  std::string b("\0\0\0\0", 4);
  b += std::string("\0\0\0\1", 4) + std::string("\0\0\0\2", 4) + std::string("\0\0\0\1\0", 5);
  b += std::string(3, '\0') + std::string("\0\0\0\0", 4);  // pad, name: 0 entries
  b += std::string(12, '\0');                              // 3 empty float64 sequences
  const JointStateMsg m = decodeJointState(b, "be");
  EXPECT_EQ(m.header.stamp.sec, 1);
  EXPECT_EQ(m.header.stamp.nanosec, 2u);
}

TEST(Cdr, EveryTruncationIsAnInputErrorNamingTheField) {
  OdometryMsg m;
  m.header.frame_id = "odom";
  const std::string b = encodeCdr(m);
  for (std::size_t n = 0; n < b.size(); ++n) {
    try {
      decodeOdometry(b.substr(0, n), "bag.mcap: offset 9");
      ADD_FAILURE() << "accepted " << n << " of " << b.size() << " bytes";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("bag.mcap: offset 9"), std::string::npos);
    }
  }
}

TEST(Cdr, HugeSequenceLengthsAreRefusedBeforeAllocating) {
  LaserScanMsg s;
  std::string b = encodeCdr(s);
  // The ranges length sits right after the 7 floats: set it to 1e9.
  const std::size_t ranges_at = b.size() - 8;
  const std::uint32_t huge = 1000000000u;
  std::memcpy(b.data() + ranges_at, &huge, 4);
  EXPECT_THROW(decodeLaserScan(b, "x"), InputError);
}

TEST(RosTime, RoundsToTheNearestNanosecondAndRefusesNonFinite) {
  EXPECT_EQ(rosTimeFromSeconds(1.5, "t").nanosec, 500000000u);
  EXPECT_EQ(rosTimeFromSeconds(0.9999999999, "t").sec, 1);  // rounds up into the next second
  EXPECT_EQ(rosTimeFromSeconds(0.9999999999, "t").nanosec, 0u);
  EXPECT_EQ(rosTimeFromSeconds(-0.25, "t").sec, -1);
  EXPECT_EQ(rosTimeFromSeconds(-0.25, "t").nanosec, 750000000u);
  // Epoch-sized stamps keep nanosecond resolution: 1.7e9 s has ulp 2.4e-7 s, the split keeps it.
  EXPECT_EQ(rosTimeFromSeconds(1700000000.25, "t").nanosec, 250000000u);
  EXPECT_THROW(rosTimeFromSeconds(std::nan(""), "t"), InputError);
  EXPECT_THROW(rosTimeFromSeconds(3e9, "t"), InputError);
}

TEST(Schema, Ros2MsgTextListsEveryDependencyOnceAfterA80EqualsLine) {
  const std::string s = ros2MsgSchema(kOdometryType);
  EXPECT_EQ(s.find("std_msgs/Header header\n"), 0u);
  const std::string sep = std::string(80, '=') + "\nMSG: ";
  for (const char* dep :
       {"std_msgs/Header", "builtin_interfaces/Time", "geometry_msgs/PoseWithCovariance",
        "geometry_msgs/Pose", "geometry_msgs/Point", "geometry_msgs/Quaternion",
        "geometry_msgs/TwistWithCovariance", "geometry_msgs/Twist", "geometry_msgs/Vector3"}) {
    const auto first = s.find(sep + dep + "\n");
    EXPECT_NE(first, std::string::npos) << dep;
    EXPECT_EQ(s.find(sep + dep + "\n", first + 1), std::string::npos) << dep << " twice";
  }
  EXPECT_TRUE(ros2MsgSchema("foo_msgs/msg/Bar").empty());
}

}  // namespace
}  // namespace slamprep::eval
