#include "slamprep/eval/formats/ros2_messages.hpp"

#include <cmath>
#include <limits>
#include <map>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/cdr.hpp"

namespace slamprep::eval {
namespace {

// Field lists of the message definitions (the .msg files without their comments and default
// values, which do not change the wire format). Nested types are written fully qualified.
const std::map<std::string, std::string, std::less<>>& definitions() {
  static const std::map<std::string, std::string, std::less<>> defs = {
      {"builtin_interfaces/Time", "int32 sec\nuint32 nanosec\n"},
      {"std_msgs/Header", "builtin_interfaces/Time stamp\nstring frame_id\n"},
      {"geometry_msgs/Point", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Vector3", "float64 x\nfloat64 y\nfloat64 z\n"},
      {"geometry_msgs/Quaternion", "float64 x\nfloat64 y\nfloat64 z\nfloat64 w\n"},
      {"geometry_msgs/Pose",
       "geometry_msgs/Point position\ngeometry_msgs/Quaternion orientation\n"},
      {"geometry_msgs/PoseWithCovariance", "geometry_msgs/Pose pose\nfloat64[36] covariance\n"},
      {"geometry_msgs/Twist", "geometry_msgs/Vector3 linear\ngeometry_msgs/Vector3 angular\n"},
      {"geometry_msgs/TwistWithCovariance", "geometry_msgs/Twist twist\nfloat64[36] covariance\n"},
      {"geometry_msgs/Transform",
       "geometry_msgs/Vector3 translation\ngeometry_msgs/Quaternion rotation\n"},
      {"geometry_msgs/TransformStamped",
       "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/Transform transform\n"},
      {"sensor_msgs/LaserScan",
       "std_msgs/Header header\nfloat32 angle_min\nfloat32 angle_max\nfloat32 angle_increment\n"
       "float32 time_increment\nfloat32 scan_time\nfloat32 range_min\nfloat32 range_max\n"
       "float32[] ranges\nfloat32[] intensities\n"},
      {"nav_msgs/Odometry",
       "std_msgs/Header header\nstring child_frame_id\ngeometry_msgs/PoseWithCovariance pose\n"
       "geometry_msgs/TwistWithCovariance twist\n"},
      {"sensor_msgs/Imu",
       "std_msgs/Header header\ngeometry_msgs/Quaternion orientation\n"
       "float64[9] orientation_covariance\ngeometry_msgs/Vector3 angular_velocity\n"
       "float64[9] angular_velocity_covariance\ngeometry_msgs/Vector3 linear_acceleration\n"
       "float64[9] linear_acceleration_covariance\n"},
      {"sensor_msgs/JointState",
       "std_msgs/Header header\nstring[] name\nfloat64[] position\nfloat64[] velocity\n"
       "float64[] effort\n"},
      {"tf2_msgs/TFMessage", "geometry_msgs/TransformStamped[] transforms\n"},
  };
  return defs;
}

// The nested types a definition uses, depth first, each once.
void collectDependencies(const std::string& text, std::vector<std::string>& out) {
  std::size_t pos = 0;
  while (pos < text.size()) {
    const std::size_t end = text.find('\n', pos);
    std::string type = text.substr(pos, text.find(' ', pos) - pos);
    pos = end + 1;
    if (const auto bracket = type.find('['); bracket != std::string::npos) type.resize(bracket);
    if (type.find('/') == std::string::npos) continue;  // a primitive
    bool seen = false;
    for (const auto& t : out) seen = seen || t == type;
    if (seen) continue;
    out.push_back(type);
    collectDependencies(definitions().find(type)->second, out);
  }
}

void put(CdrWriter& w, const RosHeader& h) {
  w.i32(h.stamp.sec);
  w.u32(h.stamp.nanosec);
  w.string(h.frame_id);
}
void put(CdrWriter& w, const Quaternion& q) {
  for (double v : {q.x, q.y, q.z, q.w}) w.f64(v);
}
template <std::size_t N>
void put(CdrWriter& w, const std::array<double, N>& a) {
  for (double v : a) w.f64(v);
}

RosHeader getHeader(CdrReader& r) {
  RosHeader h;
  h.stamp.sec = r.i32("header.stamp.sec");
  h.stamp.nanosec = r.u32("header.stamp.nanosec");
  if (h.stamp.nanosec >= 1000000000u)
    throw InputError(r.where(), "header.stamp.nanosec: " + std::to_string(h.stamp.nanosec) +
                                    " is not below 1e9");
  h.frame_id = r.string("header.frame_id");
  return h;
}
Quaternion getQuaternion(CdrReader& r, const std::string& field) {
  Quaternion q;
  q.x = r.f64(field + ".x");
  q.y = r.f64(field + ".y");
  q.z = r.f64(field + ".z");
  q.w = r.f64(field + ".w");
  return q;
}
template <std::size_t N>
std::array<double, N> getArray(CdrReader& r, const std::string& field) {
  std::array<double, N> a{};
  for (double& v : a) v = r.f64(field);
  return a;
}
std::vector<double> getF64Sequence(CdrReader& r, const std::string& field) {
  std::vector<double> v(r.sequenceSize(field, 8));
  for (double& x : v) x = r.f64(field);
  return v;
}
std::vector<float> getF32Sequence(CdrReader& r, const std::string& field) {
  std::vector<float> v(r.sequenceSize(field, 4));
  for (float& x : v) x = r.f32(field);
  return v;
}

}  // namespace

RosTime rosTimeFromNanoseconds(std::int64_t ns) {
  std::int64_t sec = ns / 1000000000;
  std::int64_t rem = ns % 1000000000;
  if (rem < 0) {
    rem += 1000000000;
    --sec;
  }
  return {static_cast<std::int32_t>(sec), static_cast<std::uint32_t>(rem)};
}

RosTime rosTimeFromSeconds(double stamp_s, const std::string& where) {
  constexpr double kMax = std::numeric_limits<std::int32_t>::max();
  if (!std::isfinite(stamp_s) || std::abs(stamp_s) >= kMax)
    throw InputError(where, "stamp " + std::to_string(stamp_s) +
                                " s is not representable as a ROS time (int32 seconds)");
  // Split first so that the nanoseconds keep full precision for epoch-sized stamps.
  const double whole = std::floor(stamp_s);
  const auto ns = static_cast<std::int64_t>(std::llround((stamp_s - whole) * 1e9));
  return rosTimeFromNanoseconds(static_cast<std::int64_t>(whole) * 1000000000 + ns);
}

Quaternion quaternionFromYaw(double yaw_rad) {
  return {0.0, 0.0, std::sin(yaw_rad / 2), std::cos(yaw_rad / 2)};
}

std::string ros2MsgSchema(std::string_view type) {
  // "pkg/msg/Type" -> "pkg/Type", the key the definitions use.
  std::string key(type);
  if (const auto p = key.find("/msg/"); p != std::string::npos) key.erase(p, 4);
  const auto it = definitions().find(key);
  if (it == definitions().end()) return {};
  std::string text = it->second;
  std::vector<std::string> deps;
  collectDependencies(it->second, deps);
  for (const std::string& dep : deps)
    text += std::string(80, '=') + "\nMSG: " + dep + "\n" + definitions().find(dep)->second;
  return text;
}

std::string encodeCdr(const LaserScanMsg& m) {
  CdrWriter w;
  put(w, m.header);
  for (float v : {m.angle_min, m.angle_max, m.angle_increment, m.time_increment, m.scan_time,
                  m.range_min, m.range_max})
    w.f32(v);
  w.sequenceSize(m.ranges.size());
  for (float v : m.ranges) w.f32(v);
  w.sequenceSize(m.intensities.size());
  for (float v : m.intensities) w.f32(v);
  return w.bytes();
}

std::string encodeCdr(const OdometryMsg& m) {
  CdrWriter w;
  put(w, m.header);
  w.string(m.child_frame_id);
  put(w, m.position);
  put(w, m.orientation);
  put(w, m.pose_covariance);
  put(w, m.linear);
  put(w, m.angular);
  put(w, m.twist_covariance);
  return w.bytes();
}

std::string encodeCdr(const ImuMsg& m) {
  CdrWriter w;
  put(w, m.header);
  put(w, m.orientation);
  put(w, m.orientation_covariance);
  put(w, m.angular_velocity);
  put(w, m.angular_velocity_covariance);
  put(w, m.linear_acceleration);
  put(w, m.linear_acceleration_covariance);
  return w.bytes();
}

std::string encodeCdr(const JointStateMsg& m) {
  CdrWriter w;
  put(w, m.header);
  w.sequenceSize(m.name.size());
  for (const auto& n : m.name) w.string(n);
  for (const auto* seq : {&m.position, &m.velocity, &m.effort}) {
    w.sequenceSize(seq->size());
    for (double v : *seq) w.f64(v);
  }
  return w.bytes();
}

std::string encodeCdr(const TfMsg& m) {
  CdrWriter w;
  w.sequenceSize(m.transforms.size());
  for (const auto& t : m.transforms) {
    put(w, t.header);
    w.string(t.child_frame_id);
    put(w, t.translation);
    put(w, t.rotation);
  }
  return w.bytes();
}

LaserScanMsg decodeLaserScan(std::string_view cdr, const std::string& where) {
  CdrReader r(cdr, where);
  LaserScanMsg m;
  m.header = getHeader(r);
  m.angle_min = r.f32("angle_min");
  m.angle_max = r.f32("angle_max");
  m.angle_increment = r.f32("angle_increment");
  m.time_increment = r.f32("time_increment");
  m.scan_time = r.f32("scan_time");
  m.range_min = r.f32("range_min");
  m.range_max = r.f32("range_max");
  m.ranges = getF32Sequence(r, "ranges");
  m.intensities = getF32Sequence(r, "intensities");
  return m;
}

OdometryMsg decodeOdometry(std::string_view cdr, const std::string& where) {
  CdrReader r(cdr, where);
  OdometryMsg m;
  m.header = getHeader(r);
  m.child_frame_id = r.string("child_frame_id");
  m.position = getArray<3>(r, "pose.pose.position");
  m.orientation = getQuaternion(r, "pose.pose.orientation");
  m.pose_covariance = getArray<36>(r, "pose.covariance");
  m.linear = getArray<3>(r, "twist.twist.linear");
  m.angular = getArray<3>(r, "twist.twist.angular");
  m.twist_covariance = getArray<36>(r, "twist.covariance");
  return m;
}

ImuMsg decodeImu(std::string_view cdr, const std::string& where) {
  CdrReader r(cdr, where);
  ImuMsg m;
  m.header = getHeader(r);
  m.orientation = getQuaternion(r, "orientation");
  m.orientation_covariance = getArray<9>(r, "orientation_covariance");
  m.angular_velocity = getArray<3>(r, "angular_velocity");
  m.angular_velocity_covariance = getArray<9>(r, "angular_velocity_covariance");
  m.linear_acceleration = getArray<3>(r, "linear_acceleration");
  m.linear_acceleration_covariance = getArray<9>(r, "linear_acceleration_covariance");
  return m;
}

JointStateMsg decodeJointState(std::string_view cdr, const std::string& where) {
  CdrReader r(cdr, where);
  JointStateMsg m;
  m.header = getHeader(r);
  m.name.resize(r.sequenceSize("name", 4));
  for (auto& n : m.name) n = r.string("name");
  m.position = getF64Sequence(r, "position");
  m.velocity = getF64Sequence(r, "velocity");
  m.effort = getF64Sequence(r, "effort");
  return m;
}

TfMsg decodeTf(std::string_view cdr, const std::string& where) {
  CdrReader r(cdr, where);
  TfMsg m;
  // Smallest transform: header (4+4+4) + child (4) + 7 doubles.
  m.transforms.resize(r.sequenceSize("transforms", 16 + 56));
  for (auto& t : m.transforms) {
    t.header = getHeader(r);
    t.child_frame_id = r.string("child_frame_id");
    t.translation = getArray<3>(r, "transform.translation");
    t.rotation = getQuaternion(r, "transform.rotation");
  }
  return m;
}

}  // namespace slamprep::eval
