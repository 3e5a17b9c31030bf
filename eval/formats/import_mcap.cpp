#include <algorithm>
#include <cmath>
#include <limits>

#include "core/error.hpp"
#include "core/odometry.hpp"
#include "eval/formats/import.hpp"
#include "eval/formats/import_common.hpp"
#include "eval/formats/mcap.hpp"
#include "eval/formats/ros2_messages.hpp"
#include "eval/formats/text_io.hpp"
#include "eval/formats/tum.hpp"

namespace slamprep::eval {
namespace {

std::string normalType(std::string name) {
  if (const auto p = name.find("/msg/"); p != std::string::npos) name.erase(p, 4);
  return name;
}

/// The channel carrying `type`: the one named `topic`, else the only one, else `preferred`.
const McapChannel* findChannel(const McapFile& f, std::string_view type, const std::string& topic,
                               const std::string& preferred, const std::string& file,
                               const char* flag) {
  std::vector<const McapChannel*> found;
  const std::string want = normalType(std::string(type));
  for (const auto& [id, ch] : f.channels) {
    const auto s = f.schemas.find(ch.schema_id);
    if (s == f.schemas.end() || normalType(s->second.name) != want) continue;
    if (!topic.empty() && ch.topic != topic) continue;
    if (ch.message_encoding != "cdr")
      throw InputError(file, "topic " + ch.topic + ": message encoding \"" + ch.message_encoding +
                                 "\" is not supported (only cdr, the ROS 2 encoding)");
    found.push_back(&ch);
  }
  if (!topic.empty() && found.empty())
    throw InputError(file, std::string(flag) + " " + topic + ": no " + std::string(type) +
                               " channel with that topic");
  if (found.size() == 1) return found[0];
  for (const McapChannel* ch : found)
    if (ch->topic == preferred) return ch;
  if (found.size() > 1) {
    std::string list;
    for (const auto* ch : found) list += " " + ch->topic;
    throw InputError(file,
                     std::string(type) + " on several topics (" + list + " ): choose with " + flag);
  }
  return nullptr;
}

/// The channel's messages in log-time order (file order for equal times).
std::vector<const McapMessage*> messagesOf(const McapFile& f, const McapChannel* ch) {
  std::vector<const McapMessage*> out;
  if (!ch) return out;
  for (const auto& m : f.messages)
    if (m.channel_id == ch->id) out.push_back(&m);
  std::stable_sort(out.begin(), out.end(), [](const McapMessage* a, const McapMessage* b) {
    return a->log_time_ns < b->log_time_ns;
  });
  return out;
}

std::string messageWhere(const std::string& file, const McapMessage& m, const std::string& topic) {
  return file + ": offset " + std::to_string(m.file_offset) + ": " + topic + " message " +
         std::to_string(m.sequence);
}

void requireFinite(double v, const std::string& where, const char* field) {
  if (!std::isfinite(v)) throw InputError(where, std::string(field) + ": not finite");
}

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

std::size_t jointIndex(const JointStateMsg& m, const std::string& name, const char* side,
                       const std::string& where) {
  std::vector<std::size_t> hits;
  for (std::size_t i = 0; i < m.name.size(); ++i)
    if (name.empty() ? m.name[i].find(side) != std::string::npos : m.name[i] == name)
      hits.push_back(i);
  if (hits.size() != 1)
    throw InputError(where, std::string("name: ") + (hits.empty() ? "no " : "more than one ") +
                                side + " wheel joint" + (name.empty() ? "" : " named " + name) +
                                " (choose with --" + side + "-joint)");
  if (hits[0] >= m.position.size())
    throw InputError(where, "position: " + std::to_string(m.position.size()) +
                                " entries for joint " + std::to_string(hits[0]));
  return hits[0];
}

/// The LaserScan messages as scans (and each message's place, for errors); returns the frame_id
/// of the first.
std::string readScans(const McapFile& f, const McapChannel* scan_ch, const std::string& file,
                      Dataset& d, std::vector<std::string>& scan_where) {
  std::string laser_frame;
  for (const McapMessage* m : messagesOf(f, scan_ch)) {
    const std::string where = messageWhere(file, *m, scan_ch->topic);
    const LaserScanMsg msg = decodeLaserScan(m->data, where);
    ScanRecord r;
    r.scan = scanFromMsg(msg, where);
    if (!d.scans.empty())
      slamprep::eval::requireIncreasing(d.scans.back().scan.stamp_s, r.scan.stamp_s, {where, 0},
                                        "header.stamp");
    if (laser_frame.empty()) laser_frame = msg.header.frame_id;
    d.scans.push_back(std::move(r));
    scan_where.push_back(where);
  }
  if (d.scans.empty()) throw InputError(file, scan_ch->topic + ": no messages");
  return laser_frame;
}

/// The Odometry messages' poses (empty without an odometry channel).
PoseSeries readOdometry(const McapFile& f, const McapChannel* odom_ch, const std::string& file) {
  PoseSeries odom;
  for (const McapMessage* m : messagesOf(f, odom_ch)) {
    const std::string where = messageWhere(file, *m, odom_ch->topic);
    const OdometryMsg msg = decodeOdometry(m->data, where);
    const auto& q = msg.orientation;
    for (double v : {msg.position[0], msg.position[1], q.x, q.y, q.z, q.w})
      requireFinite(v, where, "pose.pose");
    if (q.x * q.x + q.y * q.y + q.z * q.z + q.w * q.w < 1e-12)
      throw InputError(where, "pose.pose.orientation: zero quaternion");
    const double t = msg.header.stamp.seconds();
    if (!odom.empty())
      slamprep::eval::requireIncreasing(odom.backStamp(), t, {where, 0}, "header.stamp");
    odom.push_back(t, SE2(msg.position[0], msg.position[1],
                          slamprep::eval::yawFromQuaternion(q.x, q.y, q.z, q.w)));
  }
  return odom;
}

/// The wheel joints' angles of the JointState messages as encoder ticks.
EncoderLog readJointEncoders(const McapFile& f, const McapChannel* joint_ch,
                             const std::string& file, const ImportParams& p) {
  const double rad_per_tick = radiansPerTick(p.ticks_per_revolution);
  EncoderLog encoders;
  for (const McapMessage* m : messagesOf(f, joint_ch)) {
    const std::string where = messageWhere(file, *m, joint_ch->topic);
    const JointStateMsg msg = decodeJointState(m->data, where);
    const std::size_t l = jointIndex(msg, p.left_joint, "left", where);
    const std::size_t r = jointIndex(msg, p.right_joint, "right", where);
    requireFinite(msg.position[l], where, "position");
    requireFinite(msg.position[r], where, "position");
    const double t = msg.header.stamp.seconds();
    if (!encoders.empty())
      slamprep::eval::requireIncreasing(encoders.back().stamp_s, t, {where, 0}, "header.stamp");
    encoders.push_back({t, ticksOf(msg.position[l], rad_per_tick, where),
                        ticksOf(msg.position[r], rad_per_tick, where)});
  }
  if (encoders.size() < 2) throw InputError(file, joint_ch->topic + ": fewer than 2 messages");
  return encoders;
}

/// The Imu messages: yaw rate and planar acceleration (empty without an IMU channel).
ImuLog readImu(const McapFile& f, const McapChannel* imu_ch, const std::string& file) {
  ImuLog imu;
  for (const McapMessage* m : messagesOf(f, imu_ch)) {
    const std::string where = messageWhere(file, *m, imu_ch->topic);
    const ImuMsg msg = decodeImu(m->data, where);
    ImuSample s{msg.header.stamp.seconds(), msg.angular_velocity[2], msg.linear_acceleration[0],
                msg.linear_acceleration[1]};
    for (double v : {s.gyro_z_radps, s.accel_x_mps2, s.accel_y_mps2})
      requireFinite(v, where, "imu");
    if (!imu.empty())
      slamprep::eval::requireIncreasing(imu.back().stamp_s, s.stamp_s, {where, 0}, "header.stamp");
    imu.push_back(s);
  }
  return imu;
}

/// The lidar mount from /tf_static (parent frame taken as the base): the transform whose child
/// is `laser_frame`; notes where it came from in `info`. nullopt when the log has none.
std::optional<SE2> mountFromTfStatic(const McapFile& f, const std::string& laser_frame,
                                     const std::string& file, DatasetInfo& info) {
  std::optional<SE2> mount;
  for (const auto& [id, ch] : f.channels) {
    if (mount || ch.topic != "/tf_static") continue;
    const auto s = f.schemas.find(ch.schema_id);
    if (s == f.schemas.end() || normalType(s->second.name) != normalType(std::string(kTfType)))
      continue;
    for (const McapMessage* m : messagesOf(f, &ch)) {
      const TfMsg tf = decodeTf(m->data, messageWhere(file, *m, ch.topic));
      for (const auto& t : tf.transforms) {
        if (t.child_frame_id != laser_frame) continue;
        const auto& q = t.rotation;
        mount = SE2(t.translation[0], t.translation[1],
                    slamprep::eval::yawFromQuaternion(q.x, q.y, q.z, q.w));
        info.config["lidar_mount_from"] = "/tf_static " + t.header.frame_id + " -> " + laser_frame;
      }
    }
  }
  return mount;
}

}  // namespace

ImportResult importMcap(std::string_view bytes, const std::string& file, const ImportParams& p) {
  checkParams(p);
  const DiffDriveParams nominal = p.nominal_geometry.value_or(DiffDriveParams{});
  const McapFile f = readMcap(bytes, file);
  ImportResult result;
  Dataset& d = result.dataset;
  const McapChannel* scan_ch =
      findChannel(f, kLaserScanType, p.scan_topic, "/scan", file, "--scan-topic");
  if (!scan_ch) throw InputError(file, "no sensor_msgs/msg/LaserScan channel");
  const McapChannel* odom_ch =
      findChannel(f, kOdometryType, p.odom_topic, "/odom", file, "--odom-topic");
  const McapChannel* joint_ch =
      findChannel(f, kJointStateType, p.joint_topic, "/joint_states", file, "--joint-topic");
  const McapChannel* imu_ch = findChannel(f, kImuType, p.imu_topic, "/imu", file, "--imu-topic");
  if (!odom_ch && !joint_ch)
    throw InputError(file,
                     "needs nav_msgs/msg/Odometry or sensor_msgs/msg/JointState besides the "
                     "LaserScan topic " +
                         scan_ch->topic);

  std::vector<std::string> scan_where;
  const std::string laser_frame = readScans(f, scan_ch, file, d, scan_where);
  const PoseSeries odom = readOdometry(f, odom_ch, file);
  std::string encoders_from;
  if (joint_ch) {
    d.encoders = readJointEncoders(f, joint_ch, file, p);
    // Start where the logged odometry is at the first joint sample, if there is one.
    const SE2 start = odom.at(d.encoders.front().stamp_s).value_or(SE2());
    d.odom_nominal = integrateEncoders(d.encoders, nominal, p.ticks_per_revolution, start);
    encoders_from = "JointState " + joint_ch->topic;
  } else {
    if (odom.size() < 2) throw InputError(file, odom_ch->topic + ": fewer than 2 messages");
    double lateral = 0.0;
    d.encoders = encodersFromPoses(odom, nominal, p.ticks_per_revolution, &lateral);
    d.odom_nominal = odom;
    encoders_from = "derived from Odometry " + odom_ch->topic + " with the nominal geometry";
    if (lateral > 1e-6)
      result.notes.push_back("odometry has sideways steps up to " + std::to_string(lateral) +
                             " m that no wheel motion explains (dropped from the encoders)");
  }
  d.info = importedInfo(p, nominal, file, "mcap", encoders_from);
  d.info.config["scan_topic"] = scan_ch->topic;
  d.imu = readImu(f, imu_ch, file);

  std::optional<SE2> mount = p.T_base_lidar;
  if (!mount) mount = mountFromTfStatic(f, laser_frame, file, d.info);
  if (!mount) result.notes.push_back("no lidar mount in the log (/tf_static): identity assumed");
  d.info.T_base_lidar = mount.value_or(SE2());
  if (!std::isfinite(d.info.T_base_lidar.x) || !std::isfinite(d.info.T_base_lidar.y) ||
      !std::isfinite(d.info.T_base_lidar.yaw))
    throw InputError(file, "/tf_static: lidar mount not finite");
  attachOdometry(d, p.trim, scan_where, result.notes);
  return result;
}

}  // namespace slamprep::eval
