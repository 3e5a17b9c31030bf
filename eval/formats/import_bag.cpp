// A ROS 2 bag -> dataset (docs/export.md, "Reading a ROS 2 bag"): any storage (sqlite3 or MCAP,
// split files, FILE or MESSAGE zstd compression) read message by message, the chosen topics
// decoded into the dataset's values as they stream by.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <deque>
#include <memory>
#include <numbers>
#include <optional>

#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/core/order_statistics.hpp"
#include "slamprep/eval/formats/bag_open.hpp"
#include "slamprep/eval/formats/bag_storage.hpp"
#include "slamprep/eval/formats/bag_topics.hpp"
#include "slamprep/eval/formats/compression.hpp"
#include "slamprep/eval/formats/import.hpp"
#include "slamprep/eval/formats/import_common.hpp"
#include "slamprep/eval/formats/range_limit.hpp"
#include "slamprep/eval/formats/ros2_messages.hpp"
#include "slamprep/eval/formats/ros_samples.hpp"
#include "slamprep/eval/formats/rosbag2.hpp"
#include "slamprep/eval/formats/scan_spill.hpp"
#include "slamprep/eval/formats/stale_odometry.hpp"
#include "slamprep/eval/formats/text_io.hpp"
#include "slamprep/eval/formats/tf_tree.hpp"
#include "slamprep/eval/formats/twist_spikes.hpp"

namespace slamprep::eval {
namespace {

constexpr double kMaxTiltRad = 2.0 * std::numbers::pi / 180.0;

// Inside the spill directory, removed before the directory is published.
constexpr const char* kSpillFile = ".scans.spill";

enum class Role { kNone, kScan, kOdom, kJoint, kImu, kTf, kTfStatic };

/// Where a message sits, kept per sample (the text is built only for an error).
struct Place {
  std::size_t file = 0;
  std::uint64_t position = 0;  ///< MCAP byte offset, sqlite row id
  std::uint32_t sequence = 0;
  Role role = Role::kNone;
};

/// The storage files of a bag as errors name them.
struct BagFileNames {
  std::vector<std::string> names;
  std::vector<char> sqlite;  ///< per file: positions are row ids, not byte offsets
};

std::string placeText(const BagFileNames& files, const std::map<Role, std::string>& topics,
                      const Place& p) {
  return files.names[p.file] + (files.sqlite[p.file] ? ": messages row " : ": offset ") +
         std::to_string(p.position) + ": " + topics.at(p.role) + " message " +
         std::to_string(p.sequence);
}

template <typename T>
struct Sample {
  std::uint64_t log_ns;
  Place place;
  T value;
};

/// The topics read and what the pass over the bag keeps of them: decoded values, not messages.
/// Samples as they are read: a deque grows without copying what it holds (a 2-hour bag has
/// 1.6 M IMU samples; a vector's doubling held up to three times their size at once).
template <typename T>
using Samples = std::deque<Sample<T>>;

/// A scan parked in the spill file: its stamp (for the order checks) and where it starts.
struct SpilledScan {
  double stamp_s = 0.0;
  std::uint64_t offset = 0;
};

struct BagData {
  BagFileNames files;
  std::string format;  ///< the storage: "mcap" or "sqlite3"
  std::map<Role, std::string> topics;
  bool message_compressed = false;  ///< compression_mode MESSAGE: each message is a zstd frame
  Samples<LaserScan> scans;         ///< without a spill
  ScanSpill* spill = nullptr;       ///< with one: the scans go there ...
  Samples<SpilledScan> spilled;     ///< ... and this is what stays in memory
  std::string laser_frame;
  std::string imu_frame;  ///< of the first Imu message
  Samples<OdometrySample> odom;
  Samples<EncoderSample> joints;
  Samples<ImuSample> imu;
  TfTree tf;
  std::optional<DiffDriveParams> geometry;  ///< from slamprep's Metadata record
  RangeHistogram ranges;                    ///< of the scans as logged
  std::size_t beams_min = 0, beams_max = 0;
  std::size_t cut_by_max_range = 0;
  bool gyro_heading = false;  ///< the record says the Odometry's heading is the gyro's

  std::string where(const Place& p) const { return placeText(files, topics, p); }
  bool anyScan() const { return !scans.empty() || !spilled.empty(); }
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

/// The array put in the order the beams were taken: the last beam first, angles running back.
void reverseBeams(LaserScan& scan) {
  if (scan.ranges_m.empty()) return;
  scan.angle_min_rad += double(scan.size() - 1) * scan.angle_increment_rad;
  scan.angle_increment_rad = -scan.angle_increment_rad;
  std::reverse(scan.ranges_m.begin(), scan.ranges_m.end());
}

/// The scan as logged goes into the range histogram; then --max-range cuts it.
void keepScan(const LaserScanMsg& msg, const BagMessage& m, const Place& place,
              const std::string& where, const ImportParams& p, BagData& d) {
  if (!d.anyScan()) d.laser_frame = msg.header.frame_id;
  if (msg.header.frame_id != d.laser_frame)
    throw InputError(where, "header.frame_id: " + msg.header.frame_id +
                                ", but the first scan's is " + d.laser_frame);
  LaserScan scan = scanFromMsg(msg, where);
  if (p.reverse_beam_time) reverseBeams(scan);
  d.beams_min = d.anyScan() ? std::min(d.beams_min, scan.size()) : scan.size();
  d.beams_max = std::max(d.beams_max, scan.size());
  d.ranges.add(scan);
  if (p.max_range_m) d.cut_by_max_range += applyMaxRange(scan, *p.max_range_m);
  if (d.spill)
    d.spilled.push_back({m.log_time_ns, place, {scan.stamp_s, d.spill->append(scan)}});
  else
    d.scans.push_back({m.log_time_ns, place, std::move(scan)});
}

void decode(const BagMessage& m, const Place& place, const ImportParams& p, BagData& d) {
  const std::string where = d.where(place);  // cheap next to the CDR decoding
  const std::string unpacked = d.message_compressed ? decompressZstd(m.data, where) : "";
  const std::string_view data = d.message_compressed ? std::string_view(unpacked) : m.data;
  switch (place.role) {
    case Role::kScan:
      keepScan(decodeLaserScan(data, where), m, place, where, p, d);
      break;
    case Role::kOdom: {
      const OdometryMsg msg = decodeOdometry(data, where);
      d.odom.push_back(
          {m.log_time_ns,
           place,
           {msg.header.stamp.seconds(), poseFromMsg(msg, where), msg.linear[0], msg.angular[2]}});
      break;
    }
    case Role::kJoint: {
      const JointStateMsg msg = decodeJointState(data, where);
      const WheelJoints w = wheelJoints(msg, p.left_joint, p.right_joint, where);
      const double rad_per_tick = radiansPerTick(p.ticks_per_revolution);
      d.joints.push_back(
          {m.log_time_ns,
           place,
           {msg.header.stamp.seconds(), ticksOf(msg.position[w.left], rad_per_tick, where),
            ticksOf(msg.position[w.right], rad_per_tick, where)}});
      break;
    }
    case Role::kImu: {
      const ImuMsg msg = decodeImu(data, where);
      if (d.imu.empty()) d.imu_frame = msg.header.frame_id;
      d.imu.push_back({m.log_time_ns, place, imuFromMsg(msg, where)});
      break;
    }
    case Role::kTf:
    case Role::kTfStatic:
      for (const auto& t : decodeTf(data, where).transforms)
        d.tf.add(t, place.role == Role::kTfStatic, where);
      break;
    case Role::kNone:
      break;
  }
}

std::optional<DiffDriveParams> geometryFrom(const McapMetadata& meta, const std::string& file) {
  std::map<std::string, double, std::less<>> values;
  for (const auto& [key, text] : meta.entries)
    if (key != kOdometryHeading)
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

/// The role of a topic id, checked against its type the first time the id is seen.
Role roleOf(const BagStorage& storage, std::uint32_t id, const BagData& d) {
  const StorageTopic& t = storage.topic(id);
  Role role = Role::kNone;
  for (const auto& [r, topic] : d.topics)
    if (topic == t.name) role = r;
  if (role != Role::kNone && t.type != normalType(typeOf(role)))
    throw InputError(storage.name(), "topic " + t.name + " (id " + std::to_string(id) +
                                         ") is not " + std::string(typeOf(role)));
  return role;
}

/// One pass over one storage file: every message of a chosen topic decoded into `d`.
void readFile(BagStorage& storage, std::size_t file, const ImportParams& p, BagData& d) {
  std::set<std::string> wanted;
  for (const auto& [role, topic] : d.topics) wanted.insert(topic);
  storage.select(wanted);
  std::map<std::uint32_t, Role> roles;  // by topic id, filled as they appear
  BagMessage m;
  while (storage.next(m)) {
    auto it = roles.find(m.topic_id);
    if (it == roles.end()) it = roles.emplace(m.topic_id, roleOf(storage, m.topic_id, d)).first;
    if (it->second != Role::kNone) decode(m, {file, m.position, m.sequence, it->second}, p, d);
  }
  for (const McapMetadata& meta : storage.metadata()) {
    if (meta.name != kSlamprepMetadata) continue;
    d.geometry = geometryFrom(meta, storage.name());
    for (const auto& [key, text] : meta.entries)
      if (key == kOdometryHeading) d.gyro_heading = text == "gyro";
  }
}

/// Sorts by log time (file order for equal times) and checks the header stamps increase.
template <typename T, typename Stamp>
void sortAndCheck(Samples<T>& samples, const BagData& d, Stamp stamp) {
  const auto by_log_time = [](const auto& a, const auto& b) { return a.log_ns < b.log_ns; };
  // Usually in order already; stable_sort would allocate a copy of them all.
  if (!std::is_sorted(samples.begin(), samples.end(), by_log_time))
    std::stable_sort(samples.begin(), samples.end(), by_log_time);
  for (std::size_t k = 1; k < samples.size(); ++k)
    requireIncreasing(stamp(samples[k - 1].value), stamp(samples[k].value),
                      {d.where(samples[k].place), 0}, "header.stamp");
}

/// The topics of every file, a topic's type the same in all.
BagTopics allTopics(const std::vector<BagStorage*>& files) {
  BagTopics topics;
  for (BagStorage* f : files)
    for (const auto& [name, t] : f->topics()) {
      const auto [it, inserted] = topics.emplace(name, t);
      if (!inserted && it->second.type != t.type)
        throw InputError(f->name(), "topic " + name + " has type " + t.type + " here but " +
                                        it->second.type + " in an earlier file of the bag");
    }
  return topics;
}

void chooseTopics(const BagTopics& topics, const ImportParams& p, const std::string& bag,
                  BagData& d) {
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
}

/// How the storage files are read: which storage, and whether each message is compressed.
struct BagLayout {
  BagStorageKind storage = BagStorageKind::kMcap;
  bool message_compressed = false;
};

BagData readBag(const std::vector<BagStorage*>& files, const BagLayout& layout,
                const ImportParams& p, const std::string& bag, ScanSpill* spill) {
  BagData d;
  d.spill = spill;
  d.format = std::string(storageName(layout.storage));
  d.message_compressed = layout.message_compressed;
  for (const BagStorage* f : files) {
    d.files.names.push_back(f->name());
    d.files.sqlite.push_back(layout.storage == BagStorageKind::kSqlite3);
  }
  chooseTopics(allTopics(files), p, bag, d);
  for (std::size_t i = 0; i < files.size(); ++i) readFile(*files[i], i, p, d);

  if (!d.anyScan()) throw InputError(bag, d.topics.at(Role::kScan) + ": no messages");
  sortAndCheck(d.scans, d, [](const LaserScan& s) { return s.stamp_s; });
  sortAndCheck(d.spilled, d, [](const SpilledScan& s) { return s.stamp_s; });
  sortAndCheck(d.odom, d, [](const OdometrySample& o) { return o.stamp_s; });
  sortAndCheck(d.joints, d, [](const EncoderSample& e) { return e.stamp_s; });
  sortAndCheck(d.imu, d, [](const ImuSample& s) { return s.stamp_s; });
  return d;
}

}  // namespace

namespace {

DiffDriveParams nominalGeometry(const BagData& d, const ImportParams& p, bool from_poses,
                                const std::string& bag, ImportSummary& s) {
  if (p.nominal_geometry) {
    s.nominal_geometry = "given (--nominal / --wheel-*)";
    return *p.nominal_geometry;
  }
  if (d.geometry) {
    s.nominal_geometry = "the bag's slamprep Metadata record";
    return *d.geometry;
  }
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

/// The logged Odometry as poses: its twist spikes reported, its stale runs dropped (reported).
PoseSeries loggedOdometry(const BagData& d, ImportResult& r) {
  const std::string stream = "Odometry " + d.topics.at(Role::kOdom);
  PoseSeries odom;
  for (const auto& s : d.odom) odom.push_back(s.value.stamp_s, s.value.pose);
  r.summary.twist_spikes = findTwistSpikes(
      d.odom.size(), [&](std::size_t k) -> const OdometrySample& { return d.odom[k].value; });
  r.summary.twist_spikes->stream = stream;
  StaleReport stale;
  stale.stream = stream;
  odom = dropStaleOdometry(odom, stale);
  r.summary.stale.push_back(std::move(stale));
  return odom;
}

/// JointState ticks (their stale runs dropped) integrated with the nominal geometry, from the
/// logged odometry's pose at the first joint sample (if any); the logged odometry is kept.
void encodersFromJoints(const BagData& d, const ImportParams& p, const std::string& bag,
                        PoseSeries odom, ImportResult& r) {
  Dataset& ds = r.dataset;
  const std::string topic = d.topics.at(Role::kJoint);
  if (d.joints.size() < 2) throw InputError(bag, topic + ": fewer than 2 messages");
  const DiffDriveParams nominal = nominalGeometry(d, p, false, bag, r.summary);
  EncoderLog joints;
  joints.reserve(d.joints.size());
  for (const auto& s : d.joints) joints.push_back(s.value);
  StaleReport stale;
  stale.stream = "JointState " + topic;
  ds.encoders = dropStaleEncoders(joints, radiansPerTick(p.ticks_per_revolution), stale);
  r.summary.stale.push_back(std::move(stale));
  ds.info = importedInfo(p, nominal, bag, d.format.c_str(), "JointState " + topic, "joint_states");
  if (d.gyro_heading && odom.size() >= 2) {
    // The Odometry's heading is the gyro's: no integration of the joints reproduces it.
    ds.odom_nominal = std::move(odom);
    ds.info.config[std::string(kOdometryHeading)] = "gyro";
    r.summary.odometry = std::to_string(d.joints.size()) + " JointState " + topic +
                         " messages: wheel angles as ticks; the nominal odometry is Odometry " +
                         d.topics.at(Role::kOdom) +
                         " as logged, its heading the integrated gyro (slamprep metadata)";
    return;
  }
  const SE2 start = odom.at(ds.encoders.front().stamp_s).value_or(SE2());
  ds.odom_nominal = integrateEncoders(ds.encoders, nominal, p.ticks_per_revolution, start);
  r.summary.odometry = std::to_string(d.joints.size()) + " JointState " + topic +
                       " messages: wheel angles as ticks, integrated with the nominal geometry";
  if (!odom.empty())
    r.summary.odometry += "; Odometry " + d.topics.at(Role::kOdom) + " (" +
                          std::to_string(odom.size()) + " poses) kept as odometry_logged.tum";
  ds.odometry_logged = std::move(odom);
}

/// Encoders and nominal odometry: from JointState when the bag has it, else ticks derived from
/// the Odometry poses.
void attachEncoders(const BagData& d, const ImportParams& p, const std::string& bag,
                    ImportResult& r) {
  PoseSeries odom;
  if (d.topics.count(Role::kOdom)) odom = loggedOdometry(d, r);
  if (d.topics.count(Role::kJoint)) return encodersFromJoints(d, p, bag, std::move(odom), r);
  Dataset& ds = r.dataset;
  const std::string topic = d.topics.at(Role::kOdom);
  if (odom.size() < 2) throw InputError(bag, topic + ": fewer than 2 messages");
  const DiffDriveParams nominal = nominalGeometry(d, p, true, bag, r.summary);
  double lateral = 0.0;
  ds.encoders = encodersFromPoses(odom, nominal, p.ticks_per_revolution, &lateral);
  r.summary.odometry = std::to_string(d.odom.size()) + " Odometry " + topic +
                       " poses: ticks derived from them with the nominal geometry";
  ds.odom_nominal = std::move(odom);
  ds.info = importedInfo(p, nominal, bag, d.format.c_str(),
                         "derived from Odometry " + topic + " with the nominal geometry",
                         "odometry_poses");
  if (lateral > 1e-6)
    r.notes.push_back("odometry has sideways steps up to " + std::to_string(lateral) +
                      " m that no wheel motion explains (dropped from the encoders)");
}

template <typename T>
void release(Samples<T>& v) {
  Samples<T>().swap(v);
}

/// An upside-down lidar's scan seen from above: beam angles negated.
void mirror(LaserScan& scan) {
  scan.angle_min_rad = -scan.angle_min_rad;
  scan.angle_increment_rad = -scan.angle_increment_rad;
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
    for (ScanRecord& s : r.dataset.scans) mirror(s.scan);
    info.config["lidar_upside_down"] = "true";
    r.notes.push_back("lidar mounted upside down (tf " + path.frames +
                      "): beam angles negated, so the scans are clockwise in the base frame");
  }
  if (path.has_dynamic && (path.motion_m > 1e-3 || path.motion_rad > 1e-3))
    r.notes.push_back("the lidar mount moves along the bag (a /tf edge of " + path.frames +
                      " moves up to " + std::to_string(path.motion_m) + " m, " +
                      std::to_string(path.motion_rad) + " rad): its first value is used");
}

/// The gyro in the base frame. For planar motion the base turns about its z axis only, so an IMU
/// whose z axis is tilted by t from the base's reads gyro_z = R_zz w (R = R_base_imu, R_zz =
/// cos t, -1 upside down): w = gyro_z / R_zz, exact at any tilt up to 60 degrees; beyond, the IMU
/// says little of the yaw rate and is left out. The accelerometer's x, y turn with the 2 x 2 block
/// of R where the IMU is level or upside down (no method reads them).
void levelImu(const BagData& d, const ImportParams& p, ImportResult& r) {
  std::vector<ImuSample>& imu = r.dataset.imu;
  if (imu.empty() || d.imu_frame.empty() || d.imu_frame == p.base_frame) return;
  TfPath path;
  const auto T =
      d.tf.has(d.imu_frame) ? d.tf.lookup(p.base_frame, d.imu_frame, &path) : std::nullopt;
  if (!T) {
    r.notes.push_back("no tf transform from " + p.base_frame + " reaches the IMU's frame \"" +
                      d.imu_frame + "\": its z axis taken as the base's");
    return;
  }
  const Eigen::Matrix3d R = T->linear();
  r.dataset.info.config["imu_mount_from"] = "tf " + path.frames;
  if (R == Eigen::Matrix3d::Identity()) return;
  if (std::abs(R(2, 2)) < 0.5) {
    r.notes.push_back("the IMU (tf " + path.frames + ") is tilted " +
                      std::to_string(std::acos(std::clamp(std::abs(R(2, 2)), 0.0, 1.0)) * 180 /
                                     std::numbers::pi) +
                      " deg from the base's z axis: its gyro does not measure the yaw rate, the "
                      "IMU is left out");
    imu.clear();
    return;
  }
  const bool planar = std::abs(std::abs(R(2, 2)) - 1.0) <= 1.0 - std::cos(kMaxTiltRad);
  const Eigen::Matrix2d M = R.topLeftCorner<2, 2>();
  for (ImuSample& s : imu) {
    s.gyro_z_radps /= R(2, 2);
    if (!planar) continue;
    const Eigen::Vector2d a = M * Eigen::Vector2d(s.accel_x_mps2, s.accel_y_mps2);
    s.accel_x_mps2 = a.x();
    s.accel_y_mps2 = a.y();
  }
  if (R(2, 2) < 0.0)
    r.notes.push_back("IMU mounted upside down (tf " + path.frames + "): its gyro z negated");
  if (!planar)
    r.notes.push_back("the IMU (tf " + path.frames + ") is tilted: its gyro z divided by " +
                      std::to_string(R(2, 2)) + ", its accelerometer kept as logged");
}

/// Scans whose time_increment --time-increment replaced, and those left at 0.
struct TimeIncrementCounts {
  std::size_t replaced = 0, zero = 0, derived = 0;
  double zero_angle_increment_rad = 0.0;  ///< of a scan without one: its beams' spacing
  double period_s = 0.0;                  ///< the scans' median period (medianSpacing)
};

/// A head that turns once per scan takes its beams period |angle_increment| / 2 pi apart.
double oneTurnIncrement(double period_s, double angle_increment_rad) {
  return period_s * std::abs(angle_increment_rad) / (2.0 * std::numbers::pi);
}

void applyTimeIncrement(LaserScan& scan, const ImportParams& p, TimeIncrementCounts& counts) {
  if (p.time_increment_s) {
    if (scan.time_increment_s != 0 && scan.time_increment_s != *p.time_increment_s)
      ++counts.replaced;
    scan.time_increment_s = *p.time_increment_s;
  }
  if (scan.time_increment_s == 0 && p.time_increment_one_turn && counts.period_s > 0.0) {
    scan.time_increment_s = oneTurnIncrement(counts.period_s, scan.angle_increment_rad);
    ++counts.derived;
  }
  if (scan.time_increment_s == 0) {
    ++counts.zero;
    counts.zero_angle_increment_rad = std::abs(scan.angle_increment_rad);
  }
}

void addTimeIncrementNotes(const TimeIncrementCounts& c, std::size_t scans,
                           std::vector<std::string>& notes) {
  const std::string n = std::to_string(scans);
  char text[200];
  if (c.replaced)
    notes.push_back("--time-increment replaced a different time_increment in " +
                    std::to_string(c.replaced) + " of " + n + " scans");
  if (c.derived) {
    std::snprintf(text, sizeof text,
                  "--time-increment auto: %zu of %s scans had time_increment 0 and were given one "
                  "turn per scan of their median period, %.4g s",
                  c.derived, n.c_str(), c.period_s);
    notes.push_back(text);
  }
  if (!c.zero) return;
  std::string hint;
  if (c.period_s > 0.0 && c.zero_angle_increment_rad > 0.0) {
    std::snprintf(text, sizeof text,
                  " (a head that turns once per scan would have %.3g s: the scans' median "
                  "period over one turn of their beam spacing; --time-increment auto gives it)",
                  oneTurnIncrement(c.period_s, c.zero_angle_increment_rad));
    hint = text;
  }
  notes.push_back(std::to_string(c.zero) + " of " + n +
                  " scans have time_increment 0 (the bag does not say when each beam was "
                  "taken): de-skew methods will refuse them; give --time-increment SECONDS" +
                  hint);
}

void setTimeIncrement(const ImportParams& p, ImportResult& r) {
  TimeIncrementCounts counts;
  std::vector<double> stamps_s;
  for (const ScanRecord& s : r.dataset.scans) stamps_s.push_back(s.scan.stamp_s);
  counts.period_s = medianSpacing(stamps_s);
  for (ScanRecord& s : r.dataset.scans) applyTimeIncrement(s.scan, p, counts);
  addTimeIncrementNotes(counts, r.dataset.scans.size(), r.notes);
}

/// The spilled scans read back in stamp order with what importBag does to scans in memory:
/// mirrored when the lidar is upside down, the time increment set, the odometry attached.
class SpilledScans final : public ScanStream {
 public:
  SpilledScans(std::unique_ptr<ScanSpill> spill, BagData& d, const Dataset& ds,
               const ImportParams& p)
      : spill_(std::move(spill)),
        stubs_(std::move(d.spilled)),
        files_(d.files),
        topics_(d.topics),
        odometry_(ds.odom_nominal),
        upside_down_(ds.info.config.value("lidar_upside_down", "") == "true"),
        params_(p) {
    std::vector<double> stamps_s;
    for (const auto& stub : stubs_) stamps_s.push_back(stub.value.stamp_s);
    counts_.period_s = medianSpacing(stamps_s);
  }

  bool next(ScanRecord& out) override {
    while (k_ < stubs_.size()) {
      const Sample<SpilledScan>& stub = stubs_[k_++];
      ScanRecord r;
      r.scan = spill_->read(stub.value.offset);
      if (upside_down_) mirror(r.scan);
      applyTimeIncrement(r.scan, params_, counts_);
      if (!attachOdometryTo(r, odometry_, params_.trim, where(stub.place))) {
        ++dropped_;
        continue;
      }
      out = std::move(r);
      ++count_;
      return true;
    }
    if (count_ == 0) throw InputError(where(stubs_.front().place), "no scan left");
    return false;
  }

  std::size_t count() const override { return count_; }

  std::vector<std::string> notes() const override {
    std::vector<std::string> notes;
    addTimeIncrementNotes(counts_, stubs_.size(), notes);
    if (dropped_) notes.push_back(trimmedNote(dropped_));
    return notes;
  }

 private:
  std::string where(const Place& p) const { return placeText(files_, topics_, p); }

  std::unique_ptr<ScanSpill> spill_;
  Samples<SpilledScan> stubs_;
  BagFileNames files_;
  std::map<Role, std::string> topics_;
  PoseSeries odometry_;
  bool upside_down_ = false;
  ImportParams params_;
  TimeIncrementCounts counts_;
  std::size_t k_ = 0, count_ = 0, dropped_ = 0;
};

/// What the summary says of the scans, the time increment and the maximum range.
void summarizeScans(const BagData& d, const ImportParams& p, std::size_t messages,
                    ImportResult& r) {
  ImportSummary& s = r.summary;
  s.scans = std::to_string(messages) + " LaserScan " + d.topics.at(Role::kScan) + " messages, " +
            std::to_string(d.beams_min) +
            (d.beams_max > d.beams_min ? ".." + std::to_string(d.beams_max) : "") +
            " beams; angles, range limits and beam timing from each message";
  s.time_increment =
      p.time_increment_s          ? std::to_string(*p.time_increment_s) + " s (--time-increment)"
      : p.time_increment_one_turn ? "each LaserScan's time_increment; where 0, one turn per scan "
                                    "(--time-increment auto)"
                                  : "each LaserScan's time_increment";
  s.range = rangeReport(d.ranges, p.max_range_m, d.cut_by_max_range);
  Dataset& ds = r.dataset;
  if (p.max_range_m) ds.info.config["max_range_m"] = *p.max_range_m;
  if (d.ranges.count() == 0)
    r.notes.push_back(
        "no scan has a valid reading (every range is non-finite or outside "
        "[range_min, range_max]): the lidar saw nothing");
  if (s.range->suspect) {
    ds.info.config["range_max_suspect"] = s.range->text();
    r.notes.push_back(s.range->text());
  } else if (s.range->no_return) {
    r.notes.push_back(s.range->noReturnText());
  }
  for (const auto& [role, topic] : d.topics) s.topics[std::string(typeOf(role))] = topic;
}

ImportResult importBag(const std::vector<BagStorage*>& files, const BagLayout& layout,
                       const ImportParams& p, const std::string& bag) {
  checkParams(p);
  if (p.base_frame.empty()) throw InputError("--base-frame", "must not be empty");
  std::unique_ptr<ScanSpill> spill;
  if (!p.spill_dir.empty()) spill = std::make_unique<ScanSpill>(p.spill_dir / kSpillFile);
  BagData d = readBag(files, layout, p, bag, spill.get());
  ImportResult r;
  attachEncoders(d, p, bag, r);
  release(d.odom);  // what a long bag holds besides its scans: freed as soon as converted
  release(d.joints);
  Dataset& ds = r.dataset;
  std::vector<std::string> scan_where;
  const std::size_t messages = d.scans.size() + d.spilled.size();
  for (auto& s : d.scans) {  // moved: a long bag's scans are most of the memory
    ScanRecord record;
    record.scan = std::move(s.value);
    ds.scans.push_back(std::move(record));
    scan_where.push_back(d.where(s.place));
  }
  ds.imu.reserve(d.imu.size());
  for (const auto& s : d.imu) ds.imu.push_back(s.value);
  release(d.imu);
  ds.info.config["scan_topic"] = d.topics.at(Role::kScan);
  if (files.size() > 1) ds.info.config["bag_files"] = std::to_string(files.size());
  summarizeScans(d, p, messages, r);
  mountLidar(d, p, r);
  levelImu(d, p, r);
  const SE2& m = ds.info.T_base_lidar;
  if (!std::isfinite(m.x) || !std::isfinite(m.y) || !std::isfinite(m.yaw))
    throw InputError(bag, "lidar mount not finite");
  r.summary.lidar_mount =
      "x " + std::to_string(m.x) + " m, y " + std::to_string(m.y) + " m, yaw " +
      std::to_string(m.yaw * 180 / std::numbers::pi) + " deg from " +
      ds.info.config.value("lidar_mount_from", std::string("nothing (identity)"));
  if (spill) {
    r.scans = std::make_unique<SpilledScans>(std::move(spill), d, ds, p);
    return r;
  }
  setTimeIncrement(p, r);
  attachOdometry(ds, p.trim, scan_where, r.notes);
  return r;
}

std::string storageText(const Rosbag2Bag& bag) {
  std::string s = std::string(storageName(bag.storage)) + ", " + std::to_string(bag.files.size()) +
                  (bag.files.size() > 1 ? " files" : " file");
  s += bag.version ? " (metadata.yaml version " + std::to_string(bag.version) + ")"
                   : " (no metadata.yaml: the file's magic)";
  if (bag.compression != BagCompressionMode::kNone)
    s += ", compression_mode " + std::string(compressionModeName(bag.compression)) + " " +
         bag.compression_format;
  return s;
}

}  // namespace

ImportResult importRosbag2(const std::filesystem::path& path, const ImportParams& p) {
  checkParams(p);
  ImportResult r;
  {
    // Closed (and its scratch folder removed) before the scans are written out.
    const OpenBag open(readRosbag2(path), p.spill_dir);
    const BagLayout layout{open.bag().storage,
                           open.bag().compression == BagCompressionMode::kMessage};
    r = importBag(open.storages(), layout, p, path.string());
    r.summary.storage = storageText(open.bag());
    r.notes.insert(r.notes.begin(), open.bag().notes.begin(), open.bag().notes.end());
    for (const std::string& n : open.notes()) r.notes.push_back(n);
  }
  return r;
}

ImportResult importMcap(const std::filesystem::path& bag, const ImportParams& p) {
  return importRosbag2(bag, p);
}

ImportResult importMcap(std::string_view bytes, const std::string& file, const ImportParams& p) {
  const auto source = memorySource(bytes, file);
  const auto storage = openMcapStorage(*source);
  return importBag({storage.get()}, BagLayout{}, p, file);
}

}  // namespace slamprep::eval
