#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>

#include "core/error.hpp"
#include "core/odometry.hpp"
#include "eval/formats/bag_topics.hpp"
#include "eval/formats/import.hpp"
#include "eval/formats/import_common.hpp"
#include "eval/formats/mcap.hpp"
#include "eval/formats/ros2_messages.hpp"
#include "eval/formats/ros_samples.hpp"
#include "eval/formats/rosbag2.hpp"
#include "eval/formats/text_io.hpp"
#include "eval/formats/tf_tree.hpp"

namespace slamprep::eval {
namespace {

constexpr double kMaxTiltRad = 2.0 * std::numbers::pi / 180.0;

enum class Role { kNone, kScan, kOdom, kJoint, kImu, kTf, kTfStatic };

/// Where a message sits, kept per sample (the text is built only for an error).
struct Place {
  std::size_t file = 0;
  std::uint64_t offset = 0;
  std::uint32_t sequence = 0;
  Role role = Role::kNone;
};

template <typename T>
struct Sample {
  std::uint64_t log_ns;
  Place place;
  T value;
};

/// The topics read and what the pass over the bag keeps of them: decoded values, not messages.
struct BagData {
  std::vector<std::string> files;
  std::map<Role, std::string> topics;
  std::vector<Sample<LaserScan>> scans;
  std::string laser_frame;
  std::vector<Sample<std::pair<double, SE2>>> odom;
  std::vector<Sample<EncoderSample>> joints;
  std::vector<Sample<ImuSample>> imu;
  TfTree tf;
  std::optional<DiffDriveParams> geometry;  ///< from slamprep's Metadata record

  std::string where(const Place& p) const {
    return files[p.file] + ": offset " + std::to_string(p.offset) + ": " + topics.at(p.role) +
           " message " + std::to_string(p.sequence);
  }
};

std::string_view typeOf(Role r) {
  switch (r) {
    case Role::kScan:
      return kLaserScanType;
    case Role::kOdom:
      return kOdometryType;
    case Role::kJoint:
      return kJointStateType;
    case Role::kImu:
      return kImuType;
    default:
      return kTfType;
  }
}

void decode(const McapMessage& m, const Place& place, const ImportParams& p, BagData& d) {
  const std::string where = d.where(place);  // cheap next to the CDR decoding
  switch (place.role) {
    case Role::kScan: {
      const LaserScanMsg msg = decodeLaserScan(m.data, where);
      if (d.scans.empty()) d.laser_frame = msg.header.frame_id;
      if (msg.header.frame_id != d.laser_frame)
        throw InputError(where, "header.frame_id: " + msg.header.frame_id +
                                    ", but the first scan's is " + d.laser_frame);
      d.scans.push_back({m.log_time_ns, place, scanFromMsg(msg, where)});
      break;
    }
    case Role::kOdom: {
      const OdometryMsg msg = decodeOdometry(m.data, where);
      d.odom.push_back(
          {m.log_time_ns, place, {msg.header.stamp.seconds(), poseFromMsg(msg, where)}});
      break;
    }
    case Role::kJoint: {
      const JointStateMsg msg = decodeJointState(m.data, where);
      const WheelJoints w = wheelJoints(msg, p.left_joint, p.right_joint, where);
      const double rad_per_tick = radiansPerTick(p.ticks_per_revolution);
      d.joints.push_back(
          {m.log_time_ns,
           place,
           {msg.header.stamp.seconds(), ticksOf(msg.position[w.left], rad_per_tick, where),
            ticksOf(msg.position[w.right], rad_per_tick, where)}});
      break;
    }
    case Role::kImu:
      d.imu.push_back({m.log_time_ns, place, imuFromMsg(decodeImu(m.data, where), where)});
      break;
    case Role::kTf:
    case Role::kTfStatic:
      for (const auto& t : decodeTf(m.data, where).transforms)
        d.tf.add(t, place.role == Role::kTfStatic, where);
      break;
    case Role::kNone:
      break;
  }
}

std::optional<DiffDriveParams> geometryFrom(const McapMetadata& meta, const std::string& file) {
  std::map<std::string, double, std::less<>> values;
  for (const auto& [key, text] : meta.entries)
    values[key] = parseFiniteDouble(text, {file + ": Metadata " + meta.name, 0}, key);
  auto get = [&](std::string_view key) {
    const auto it = values.find(key);
    if (it == values.end())
      throw InputError(file, "Metadata " + meta.name + ": " + std::string(key) + " missing");
    return it->second;
  };
  DiffDriveParams g{get(kNominalRadiusLeft), get(kNominalRadiusRight), get(kNominalWheelBase)};
  checkGeometry(g, file + ": Metadata " + meta.name);
  return g;
}

/// One pass over one file: every message of a chosen topic decoded into `d`, chunk by chunk.
void readFile(ByteSource& source, std::size_t file, const ImportParams& p, BagData& d) {
  McapReader reader(source);
  std::map<std::uint16_t, Role> roles;  // by channel id, filled as channels appear
  McapMessage m;
  while (reader.next(m)) {
    auto it = roles.find(m.channel_id);
    if (it == roles.end()) {
      const McapChannel& ch = reader.channels().at(m.channel_id);
      Role role = Role::kNone;
      for (const auto& [r, topic] : d.topics)
        if (topic == ch.topic) role = r;
      const auto schema = reader.schemas().find(ch.schema_id);
      if (role != Role::kNone && (schema == reader.schemas().end() ||
                                  normalType(schema->second.name) != normalType(typeOf(role))))
        throw InputError(source.name(), "channel " + std::to_string(ch.id) + " of " + ch.topic +
                                            " is not " + std::string(typeOf(role)));
      it = roles.emplace(m.channel_id, role).first;
    }
    if (it->second != Role::kNone) decode(m, {file, m.file_offset, m.sequence, it->second}, p, d);
  }
  for (const McapMetadata& meta : reader.metadata())
    if (meta.name == kSlamprepMetadata) d.geometry = geometryFrom(meta, source.name());
}

/// Sorts by log time (file order for equal times) and checks the header stamps increase.
template <typename T, typename Stamp>
void sortAndCheck(std::vector<Sample<T>>& samples, const BagData& d, Stamp stamp) {
  std::stable_sort(samples.begin(), samples.end(),
                   [](const auto& a, const auto& b) { return a.log_ns < b.log_ns; });
  for (std::size_t k = 1; k < samples.size(); ++k)
    requireIncreasing(stamp(samples[k - 1].value), stamp(samples[k].value),
                      {d.where(samples[k].place), 0}, "header.stamp");
}

BagData readBag(const std::vector<ByteSource*>& files, const ImportParams& p,
                const std::string& bag) {
  BagData d;
  for (const ByteSource* f : files) d.files.push_back(f->name());
  const BagTopics topics = listTopics(files);
  auto choose = [&](Role r, const std::string& chosen, const char* preferred, const char* flag) {
    const std::string t = chooseTopic(topics, typeOf(r), chosen, preferred, bag, flag);
    if (!t.empty()) d.topics[r] = t;
  };
  choose(Role::kScan, p.scan_topic, "/scan", "--scan-topic");
  if (!d.topics.count(Role::kScan)) throw InputError(bag, "no sensor_msgs/msg/LaserScan topic");
  choose(Role::kOdom, p.odom_topic, "/odom", "--odom-topic");
  choose(Role::kJoint, p.joint_topic, "/joint_states", "--joint-topic");
  choose(Role::kImu, p.imu_topic, "/imu", "--imu-topic");
  if (!d.topics.count(Role::kOdom) && !d.topics.count(Role::kJoint))
    throw InputError(bag,
                     "needs nav_msgs/msg/Odometry or sensor_msgs/msg/JointState besides the "
                     "LaserScan topic " +
                         d.topics.at(Role::kScan));
  for (const auto& [topic, role] : {std::pair{"/tf", Role::kTf}, {"/tf_static", Role::kTfStatic}})
    if (const auto it = topics.find(topic);
        it != topics.end() && it->second.type == normalType(kTfType))
      d.topics[role] = topic;
  for (std::size_t i = 0; i < files.size(); ++i) readFile(*files[i], i, p, d);

  if (d.scans.empty()) throw InputError(bag, d.topics.at(Role::kScan) + ": no messages");
  sortAndCheck(d.scans, d, [](const LaserScan& s) { return s.stamp_s; });
  sortAndCheck(d.odom, d, [](const auto& o) { return o.first; });
  sortAndCheck(d.joints, d, [](const EncoderSample& e) { return e.stamp_s; });
  sortAndCheck(d.imu, d, [](const ImuSample& s) { return s.stamp_s; });
  return d;
}

}  // namespace

namespace {

DiffDriveParams nominalGeometry(const BagData& d, const ImportParams& p, bool from_poses,
                                const std::string& bag) {
  if (p.nominal_geometry) return *p.nominal_geometry;
  if (d.geometry) return *d.geometry;
  throw InputError(
      bag,
      std::string("no nominal wheel geometry: ") +
          (from_poses ? "the encoder ticks are derived from the Odometry poses with it"
                      : "the JointState ticks are integrated into the nominal odometry with it") +
          ", and the bag does not carry one (bags exported by slamprep do). Give it with "
          "--nominal r_L,r_R,b: the wheel radii and the wheel base in metres that the "
          "robot's odometry is configured with (diff_drive_controller: wheel_radius, "
          "wheel_separation)");
}

/// Encoders and nominal odometry: JointState ticks integrated with the nominal geometry (from the
/// logged odometry's pose at the first joint sample, if any), else ticks derived from Odometry.
void attachEncoders(const BagData& d, const ImportParams& p, const std::string& bag,
                    ImportResult& r) {
  Dataset& ds = r.dataset;
  PoseSeries odom;
  for (const auto& s : d.odom) odom.push_back(s.value.first, s.value.second);
  const bool from_joints = d.topics.count(Role::kJoint) > 0;
  std::string encoders_from;
  if (from_joints) {
    if (d.joints.size() < 2)
      throw InputError(bag, d.topics.at(Role::kJoint) + ": fewer than 2 messages");
    const DiffDriveParams nominal = nominalGeometry(d, p, false, bag);
    for (const auto& s : d.joints) ds.encoders.push_back(s.value);
    const SE2 start = odom.at(ds.encoders.front().stamp_s).value_or(SE2());
    ds.odom_nominal = integrateEncoders(ds.encoders, nominal, p.ticks_per_revolution, start);
    ds.info = importedInfo(p, nominal, bag, "mcap", "JointState " + d.topics.at(Role::kJoint));
    return;
  }
  if (odom.size() < 2) throw InputError(bag, d.topics.at(Role::kOdom) + ": fewer than 2 messages");
  const DiffDriveParams nominal = nominalGeometry(d, p, true, bag);
  double lateral = 0.0;
  ds.encoders = encodersFromPoses(odom, nominal, p.ticks_per_revolution, &lateral);
  ds.odom_nominal = odom;
  ds.info = importedInfo(
      p, nominal, bag, "mcap",
      "derived from Odometry " + d.topics.at(Role::kOdom) + " with the nominal geometry");
  if (lateral > 1e-6)
    r.notes.push_back("odometry has sideways steps up to " + std::to_string(lateral) +
                      " m that no wheel motion explains (dropped from the encoders)");
}

/// The lidar mount from the tf tree (or --lidar-mount); an upside-down lidar's beam angles are
/// negated (a -> -a): its scans are then clockwise in the base frame, beams kept in the order
/// and at the times they were taken.
void mountLidar(const BagData& d, const ImportParams& p, ImportResult& r) {
  DatasetInfo& info = r.dataset.info;
  info.config["base_frame"] = p.base_frame;
  info.config["laser_frame"] = d.laser_frame;
  if (p.T_base_lidar) {
    info.T_base_lidar = *p.T_base_lidar;
    info.config["lidar_mount_from"] = "--lidar-mount";
    return;
  }
  if (d.laser_frame == p.base_frame) return;  // scans already in the base frame
  if (!d.tf.has(d.laser_frame)) {
    r.notes.push_back("no tf transform reaches the scans' frame \"" + d.laser_frame +
                      "\": lidar mount identity assumed (give --lidar-mount x,y,yaw)");
    return;
  }
  TfPath path;
  const auto T = d.tf.lookup(p.base_frame, d.laser_frame, &path);
  if (!T)
    throw InputError("tf", "no path from " + p.base_frame + " to the scans' frame " +
                               d.laser_frame + " (frames: " + d.tf.frameList() +
                               "): choose the base with --base-frame, or give --lidar-mount");
  const PlanarMount mount = planarMount(*T, path.frames, kMaxTiltRad);
  info.T_base_lidar = mount.T_base_lidar;
  info.config["lidar_mount_from"] = "tf " + path.frames;
  if (mount.upside_down) {
    for (ScanRecord& s : r.dataset.scans) {
      s.scan.angle_min_rad = -s.scan.angle_min_rad;
      s.scan.angle_increment_rad = -s.scan.angle_increment_rad;
    }
    info.config["lidar_upside_down"] = "true";
    r.notes.push_back("lidar mounted upside down (tf " + path.frames +
                      "): beam angles negated, so the scans are clockwise in the base frame");
  }
  if (path.has_dynamic && (path.motion_m > 1e-3 || path.motion_rad > 1e-3))
    r.notes.push_back("the lidar mount moves along the bag (a /tf edge of " + path.frames +
                      " moves up to " + std::to_string(path.motion_m) + " m, " +
                      std::to_string(path.motion_rad) + " rad): its first value is used");
}

void setTimeIncrement(const ImportParams& p, ImportResult& r) {
  std::size_t replaced = 0, zero = 0;
  for (ScanRecord& s : r.dataset.scans) {
    if (p.time_increment_s) {
      if (s.scan.time_increment_s != 0 && s.scan.time_increment_s != *p.time_increment_s)
        ++replaced;
      s.scan.time_increment_s = *p.time_increment_s;
    }
    if (s.scan.time_increment_s == 0) ++zero;
  }
  const std::string n = std::to_string(r.dataset.scans.size());
  if (replaced)
    r.notes.push_back("--time-increment replaced a different time_increment in " +
                      std::to_string(replaced) + " of " + n + " scans");
  if (zero)
    r.notes.push_back(std::to_string(zero) + " of " + n +
                      " scans have time_increment 0 (the bag does not say when each beam was "
                      "taken): de-skew methods will refuse them; give --time-increment SECONDS");
}

ImportResult importBag(const std::vector<ByteSource*>& files, const ImportParams& p,
                       const std::string& bag) {
  checkParams(p);
  if (p.base_frame.empty()) throw InputError("--base-frame", "must not be empty");
  BagData d = readBag(files, p, bag);
  ImportResult r;
  attachEncoders(d, p, bag, r);
  Dataset& ds = r.dataset;
  std::vector<std::string> scan_where;
  for (auto& s : d.scans) {  // moved: a long bag's scans are most of the memory
    ScanRecord record;
    record.scan = std::move(s.value);
    ds.scans.push_back(std::move(record));
    scan_where.push_back(d.where(s.place));
  }
  for (const auto& s : d.imu) ds.imu.push_back(s.value);
  ds.info.config["scan_topic"] = d.topics.at(Role::kScan);
  if (files.size() > 1) ds.info.config["bag_files"] = std::to_string(files.size());
  mountLidar(d, p, r);
  const SE2& m = ds.info.T_base_lidar;
  if (!std::isfinite(m.x) || !std::isfinite(m.y) || !std::isfinite(m.yaw))
    throw InputError(bag, "lidar mount not finite");
  setTimeIncrement(p, r);
  attachOdometry(ds, p.trim, scan_where, r.notes);
  return r;
}

}  // namespace

ImportResult importMcap(const std::filesystem::path& bag, const ImportParams& p) {
  checkParams(p);
  std::vector<std::unique_ptr<ByteSource>> sources;
  std::vector<ByteSource*> files;
  for (const auto& file : bagFiles(bag)) {
    sources.push_back(openFileSource(file));
    files.push_back(sources.back().get());
  }
  return importBag(files, p, bag.string());
}

ImportResult importMcap(std::string_view bytes, const std::string& file, const ImportParams& p) {
  const auto source = memorySource(bytes, file);
  return importBag({source.get()}, p, file);
}

}  // namespace slamprep::eval
