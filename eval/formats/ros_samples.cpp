#include "slamprep/eval/formats/ros_samples.hpp"

#include <cmath>
#include <limits>
#include <vector>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/tum.hpp"

namespace slamprep::eval {
namespace {

void requireFinite(double v, const std::string& where, const char* field) {
  if (!std::isfinite(v)) throw InputError(where, std::string(field) + ": not finite");
}

}  // namespace

LaserScan scanFromMsg(const LaserScanMsg& m, const std::string& where) {
  LaserScan s;
  s.stamp_s = m.header.stamp.seconds();
  const std::pair<const char*, float> fields[] = {{"angle_min", m.angle_min},
                                                  {"angle_max", m.angle_max},
                                                  {"angle_increment", m.angle_increment},
                                                  {"time_increment", m.time_increment},
                                                  {"scan_time", m.scan_time},
                                                  {"range_min", m.range_min}};
  for (const auto& [name, v] : fields) requireFinite(v, where, name);
  if (std::isnan(m.range_max)) throw InputError(where, "range_max: NaN");
  if (m.ranges.empty()) throw InputError(where, "ranges: empty scan (0 beams)");
  if (m.ranges.size() > 1 && m.angle_increment == 0)
    throw InputError(where,
                     "angle_increment: 0 with " + std::to_string(m.ranges.size()) + " beams");
  if (m.time_increment < 0) throw InputError(where, "time_increment: negative");
  if (m.scan_time < 0) throw InputError(where, "scan_time: negative");
  if (m.range_min < 0) throw InputError(where, "range_min: negative");
  if (!(m.range_max > m.range_min)) throw InputError(where, "range_max: not above range_min");
  s.angle_min_rad = m.angle_min;
  s.angle_increment_rad = m.angle_increment;
  s.time_increment_s = m.time_increment;
  s.scan_time_s = m.scan_time;
  s.range_min_m = m.range_min;
  s.range_max_m = m.range_max;
  s.ranges_m.reserve(m.ranges.size());
  for (float r : m.ranges)
    s.ranges_m.push_back(std::isfinite(r) ? double(r) : std::numeric_limits<double>::infinity());
  return s;
}

SE2 poseFromMsg(const OdometryMsg& m, const std::string& where) {
  const auto& q = m.orientation;
  for (double v : {m.position[0], m.position[1], q.x, q.y, q.z, q.w})
    requireFinite(v, where, "pose.pose");
  if (q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w < 1e-12)
    throw InputError(where, "pose.pose.orientation: zero quaternion");
  return {m.position[0], m.position[1], yawFromQuaternion(q.x, q.y, q.z, q.w)};
}

ImuSample imuFromMsg(const ImuMsg& m, const std::string& where) {
  const ImuSample s{m.header.stamp.seconds(), m.angular_velocity[2], m.linear_acceleration[0],
                    m.linear_acceleration[1]};
  for (double v : {s.gyro_z_radps, s.accel_x_mps2, s.accel_y_mps2}) requireFinite(v, where, "imu");
  return s;
}

namespace {

std::size_t jointIndex(const JointStateMsg& m, const std::string& name, const char* side,
                       const std::string& where) {
  std::vector<std::size_t> hits;
  for (std::size_t i = 0; i < m.name.size(); ++i)
    if (name.empty() ? m.name[i].find(side) != std::string::npos : m.name[i] == name)
      hits.push_back(i);
  if (hits.size() != 1) {
    std::string found;
    for (const auto& n : m.name) found += (found.empty() ? "" : ", ") + n;
    throw InputError(where, std::string("name: ") + (hits.empty() ? "no " : "more than one ") +
                                side + " wheel joint" +
                                (name.empty() ? " (a name containing \"" + std::string(side) + "\")"
                                              : " named " + name) +
                                " among the joints [" + found + "]: choose with --" + side +
                                "-joint NAME");
  }
  if (hits[0] >= m.position.size())
    throw InputError(where, "position: " + std::to_string(m.position.size()) +
                                " entries, none for joint " + m.name[hits[0]]);
  requireFinite(m.position[hits[0]], where, "position");
  return hits[0];
}

}  // namespace

WheelJoints wheelJoints(const JointStateMsg& m, const std::string& left, const std::string& right,
                        const std::string& where) {
  return {jointIndex(m, left, "left", where), jointIndex(m, right, "right", where)};
}

}  // namespace slamprep::eval
