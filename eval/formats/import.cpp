#include "eval/formats/import.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>

#include "core/error.hpp"
#include "core/odometry.hpp"
#include "eval/formats/carmen.hpp"
#include "eval/formats/mcap.hpp"
#include "eval/formats/ros2_messages.hpp"
#include "eval/formats/text_io.hpp"
#include "eval/formats/tum.hpp"

namespace slamprep::eval {
namespace {

/// The median spacing of the scan stamps: CARMEN has no scan_time.
double medianSpacing(const std::vector<ScanRecord>& scans) {
  std::vector<double> dt;
  for (std::size_t i = 1; i < scans.size(); ++i)
    dt.push_back(scans[i].scan.stamp_s - scans[i - 1].scan.stamp_s);
  if (dt.empty()) return 0.0;
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  return dt[dt.size() / 2];
}

void checkGeometry(const DiffDriveParams& g, const std::string& where) {
  for (double v : {g.radius_left_m, g.radius_right_m, g.wheel_base_m})
    if (!std::isfinite(v) || v <= 0) throw InputError(where, "wheel radii and base must be > 0");
}

void checkParams(const ImportParams& p) {
  if (p.nominal_geometry) checkGeometry(*p.nominal_geometry, "--wheel-radius/--wheel-base");
  if (p.ticks_per_revolution <= 0) throw InputError("--ticks-per-revolution", "must be > 0");
  if (p.time_increment_s && (!std::isfinite(*p.time_increment_s) || *p.time_increment_s < 0))
    throw InputError("--time-increment", "must be finite and >= 0");
}

/// A PARAM value of a CARMEN log as a finite number; nullopt when the log has no such PARAM.
std::optional<double> carmenParam(const CarmenLog& log, const std::string& name,
                                  const std::string& file) {
  const auto it = log.params.find(name);
  if (it == log.params.end()) return std::nullopt;
  return slamprep::eval::parseFiniteDouble(it->second.value, {file, it->second.line}, name);
}

/// Attaches the odometry to the scans; refuses (or with trim drops) scans it does not cover.
void attachOdometry(Dataset& d, bool trim, const std::vector<std::string>& scan_where,
                    std::vector<std::string>& notes) {
  std::vector<ScanRecord> kept;
  for (std::size_t i = 0; i < d.scans.size(); ++i) {
    ScanRecord& r = d.scans[i];
    if (!d.odom_nominal.covers(r.scan.stamp_s) || !d.odom_nominal.covers(r.scan.endTime())) {
      if (trim) continue;
      throw InputError(
          scan_where[i],
          "scan at " + std::to_string(r.scan.stamp_s) + ".." + std::to_string(r.scan.endTime()) +
              " s is not covered by the odometry (" +
              (d.odom_nominal.empty() ? std::string("none")
                                      : std::to_string(d.odom_nominal.frontStamp()) + ".." +
                                            std::to_string(d.odom_nominal.backStamp()) + " s") +
              "); use --trim to drop such scans");
    }
    r.T_odom_base_nominal = d.odom_nominal.at(r.scan.stamp_s);
    kept.push_back(std::move(r));
  }
  if (kept.size() < d.scans.size())
    notes.push_back(std::to_string(d.scans.size() - kept.size()) +
                    " scans outside the odometry were dropped (--trim)");
  if (kept.empty()) throw InputError(scan_where.empty() ? "" : scan_where[0], "no scan left");
  d.scans = std::move(kept);
}

DatasetInfo importedInfo(const ImportParams& p, const DiffDriveParams& nominal,
                         const std::string& file, const char* format,
                         const std::string& encoders_from) {
  DatasetInfo info;
  info.nominal_geometry = nominal;
  info.ticks_per_revolution = p.ticks_per_revolution;
  info.config = {{"imported_from", file}, {"format", format}, {"encoders", encoders_from}};
  return info;
}

// ---- MCAP ----

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

std::int64_t ticksOf(double angle_rad, double rad_per_tick, const std::string& where) {
  const double t = std::round(angle_rad / rad_per_tick);
  if (!std::isfinite(t) || std::abs(t) > 9e18)
    throw InputError(where, "wheel angle " + std::to_string(angle_rad) + " rad out of range");
  return static_cast<std::int64_t>(t);
}

}  // namespace

EncoderLog encodersFromPoses(const PoseSeries& poses, const DiffDriveParams& g,
                             int ticks_per_revolution, double* max_lateral_m) {
  EncoderLog out;
  const double rad_per_tick = radiansPerTick(ticks_per_revolution);
  double phi_l = 0.0, phi_r = 0.0, lateral = 0.0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    if (k > 0) {
      const Eigen::Vector3d xi = between(poses[k - 1].value, poses[k].value).log();
      phi_l += (xi.x() - xi.z() * g.wheel_base_m / 2) / g.radius_left_m;
      phi_r += (xi.x() + xi.z() * g.wheel_base_m / 2) / g.radius_right_m;
      lateral = std::max(lateral, std::abs(xi.y()));
    }
    const std::string where = "odometry sample " + std::to_string(k);
    out.push_back({poses[k].stamp_s, ticksOf(phi_l, rad_per_tick, where),
                   ticksOf(phi_r, rad_per_tick, where)});
  }
  if (max_lateral_m) *max_lateral_m = lateral;
  return out;
}

ImportResult importCarmen(std::string_view text, const std::string& file, const ImportParams& p) {
  checkParams(p);
  const CarmenLog log = parseCarmen(text, file);
  if (log.lasers.empty()) throw InputError(file, "no ROBOTLASER1 or FLASER lines");
  if (log.odometry.size() < 2) throw InputError(file, "fewer than 2 ODOM lines");
  ImportResult result;
  Dataset& d = result.dataset;
  DiffDriveParams nominal;
  if (p.nominal_geometry) {
    nominal = *p.nominal_geometry;
  } else {
    const auto r_L = carmenParam(log, "slamprep_nominal_r_L", file);
    const auto r_R = carmenParam(log, "slamprep_nominal_r_R", file);
    const auto b = carmenParam(log, "slamprep_nominal_b", file);
    if (r_L && r_R && b) {
      nominal = {*r_L, *r_R, *b};
      checkGeometry(nominal, file + ": PARAM slamprep_nominal_*");
    } else {
      result.notes.push_back("no nominal geometry given or in the log: r_L = r_R = " +
                             std::to_string(nominal.radius_left_m) +
                             " m, b = " + std::to_string(nominal.wheel_base_m) +
                             " m assumed (calibration results are relative to it)");
    }
  }
  double time_increment =
      p.time_increment_s.value_or(carmenParam(log, "slamprep_time_increment", file).value_or(0.0));
  if (!(time_increment >= 0)) throw InputError(file, "PARAM slamprep_time_increment: must be >= 0");
  for (const auto& o : log.odometry) d.odom_nominal.push_back(o.stamp_s, o.T_odom_base);
  double lateral = 0.0;
  d.encoders = encodersFromPoses(d.odom_nominal, nominal, p.ticks_per_revolution, &lateral);
  d.info = importedInfo(p, nominal, file, "carmen",
                        "derived from the ODOM poses with the nominal geometry");
  // The mount: laser_pose = robot_pose * T_base_lidar on every line.
  const SE2 mount = between(log.lasers[0].T_odom_base, log.lasers[0].T_odom_laser);
  double spread = 0.0;
  for (const auto& l : log.lasers) {
    const SE2 m = between(l.T_odom_base, l.T_odom_laser);
    spread = std::max({spread, std::hypot(m.x - mount.x, m.y - mount.y),
                       std::abs(normalizeAngle(m.yaw - mount.yaw))});
  }
  d.info.T_base_lidar = p.T_base_lidar.value_or(mount);
  if (!p.T_base_lidar && spread > 1e-3)
    result.notes.push_back("laser_pose vs robot_pose varies by up to " + std::to_string(spread) +
                           " (m or rad) across the log: the first line's mount was taken");
  std::vector<std::string> where;
  for (const auto& l : log.lasers) {
    ScanRecord r;
    r.scan = l.scan;
    r.scan.time_increment_s = time_increment;
    d.scans.push_back(std::move(r));
    where.push_back(file + ":" + std::to_string(l.line));
  }
  const double scan_time = medianSpacing(d.scans);
  for (auto& r : d.scans) r.scan.scan_time_s = scan_time;
  attachOdometry(d, p.trim, where, result.notes);
  if (lateral > 1e-6)
    result.notes.push_back("odometry has sideways steps up to " + std::to_string(lateral) +
                           " m that no wheel motion explains (dropped from the encoders)");
  if (time_increment == 0)
    result.notes.push_back(
        "CARMEN has no time between beams: time_increment = 0, de-skew will "
        "refuse these scans (give --time-increment)");
  if (log.skipped_lines)
    result.notes.push_back(std::to_string(log.skipped_lines) + " lines of other messages skipped");
  return result;
}

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

  // Scans.
  std::vector<std::string> scan_where;
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

  // Odometry poses.
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

  const double rad_per_tick = radiansPerTick(p.ticks_per_revolution);
  std::string encoders_from;
  if (joint_ch) {
    for (const McapMessage* m : messagesOf(f, joint_ch)) {
      const std::string where = messageWhere(file, *m, joint_ch->topic);
      const JointStateMsg msg = decodeJointState(m->data, where);
      const std::size_t l = jointIndex(msg, p.left_joint, "left", where);
      const std::size_t r = jointIndex(msg, p.right_joint, "right", where);
      requireFinite(msg.position[l], where, "position");
      requireFinite(msg.position[r], where, "position");
      const double t = msg.header.stamp.seconds();
      if (!d.encoders.empty())
        slamprep::eval::requireIncreasing(d.encoders.back().stamp_s, t, {where, 0}, "header.stamp");
      d.encoders.push_back({t, ticksOf(msg.position[l], rad_per_tick, where),
                            ticksOf(msg.position[r], rad_per_tick, where)});
    }
    if (d.encoders.size() < 2) throw InputError(file, joint_ch->topic + ": fewer than 2 messages");
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

  for (const McapMessage* m : messagesOf(f, imu_ch)) {
    const std::string where = messageWhere(file, *m, imu_ch->topic);
    const ImuMsg msg = decodeImu(m->data, where);
    ImuSample s{msg.header.stamp.seconds(), msg.angular_velocity[2], msg.linear_acceleration[0],
                msg.linear_acceleration[1]};
    for (double v : {s.gyro_z_radps, s.accel_x_mps2, s.accel_y_mps2})
      requireFinite(v, where, "imu");
    if (!d.imu.empty())
      slamprep::eval::requireIncreasing(d.imu.back().stamp_s, s.stamp_s, {where, 0},
                                        "header.stamp");
    d.imu.push_back(s);
  }

  // The mount from /tf_static (parent frame taken as the base), unless given.
  std::optional<SE2> mount = p.T_base_lidar;
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
        d.info.config["lidar_mount_from"] =
            "/tf_static " + t.header.frame_id + " -> " + laser_frame;
      }
    }
  }
  if (!mount) result.notes.push_back("no lidar mount in the log (/tf_static): identity assumed");
  d.info.T_base_lidar = mount.value_or(SE2());
  if (!std::isfinite(d.info.T_base_lidar.x) || !std::isfinite(d.info.T_base_lidar.y) ||
      !std::isfinite(d.info.T_base_lidar.yaw))
    throw InputError(file, "/tf_static: lidar mount not finite");
  attachOdometry(d, p.trim, scan_where, result.notes);
  return result;
}

}  // namespace slamprep::eval
