#include <algorithm>
#include <cmath>
#include <deque>
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
#include "eval/formats/scan_spill.hpp"
#include "eval/formats/text_io.hpp"
#include "eval/formats/tf_tree.hpp"

namespace slamprep::eval {
namespace {

constexpr double kMaxTiltRad = 2.0 * std::numbers::pi / 180.0;

// Inside the spill directory, removed before the directory is published.
constexpr const char* kSpillFile = ".scans.spill";

enum class Role { kNone, kScan, kOdom, kJoint, kImu, kTf, kTfStatic };

/// Where a message sits, kept per sample (the text is built only for an error).
struct Place {
  std::size_t file = 0;
  std::uint64_t offset = 0;
  std::uint32_t sequence = 0;
  Role role = Role::kNone;
};

std::string placeText(const std::vector<std::string>& files,
                      const std::map<Role, std::string>& topics, const Place& p) {
  return files[p.file] + ": offset " + std::to_string(p.offset) + ": " + topics.at(p.role) +
         " message " + std::to_string(p.sequence);
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
  std::vector<std::string> files;
  std::map<Role, std::string> topics;
  Samples<LaserScan> scans;      ///< without a spill
  ScanSpill* spill = nullptr;    ///< with one: the scans go there ...
  Samples<SpilledScan> spilled;  ///< ... and this is what stays in memory
  std::string laser_frame;
  Samples<std::pair<double, SE2>> odom;
  Samples<EncoderSample> joints;
  Samples<ImuSample> imu;
  TfTree tf;
  std::optional<DiffDriveParams> geometry;  ///< from slamprep's Metadata record
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

void decode(const McapMessage& m, const Place& place, const ImportParams& p, BagData& d) {
  const std::string where = d.where(place);  // cheap next to the CDR decoding
  switch (place.role) {
    case Role::kScan: {
      const LaserScanMsg msg = decodeLaserScan(m.data, where);
      if (!d.anyScan()) d.laser_frame = msg.header.frame_id;
      if (msg.header.frame_id != d.laser_frame)
        throw InputError(where, "header.frame_id: " + msg.header.frame_id +
                                    ", but the first scan's is " + d.laser_frame);
      LaserScan scan = scanFromMsg(msg, where);
      if (d.spill)
        d.spilled.push_back({m.log_time_ns, place, {scan.stamp_s, d.spill->append(scan)}});
      else
        d.scans.push_back({m.log_time_ns, place, std::move(scan)});
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
  for (const McapMetadata& meta : reader.metadata()) {
    if (meta.name != kSlamprepMetadata) continue;
    d.geometry = geometryFrom(meta, source.name());
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

BagData readBag(const std::vector<ByteSource*>& files, const ImportParams& p,
                const std::string& bag, ScanSpill* spill) {
  BagData d;
  d.spill = spill;
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

  if (!d.anyScan()) throw InputError(bag, d.topics.at(Role::kScan) + ": no messages");
  sortAndCheck(d.scans, d, [](const LaserScan& s) { return s.stamp_s; });
  sortAndCheck(d.spilled, d, [](const SpilledScan& s) { return s.stamp_s; });
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
    ds.encoders.reserve(d.joints.size());
    for (const auto& s : d.joints) ds.encoders.push_back(s.value);
    ds.info = importedInfo(p, nominal, bag, "mcap", "JointState " + d.topics.at(Role::kJoint));
    if (d.gyro_heading && odom.size() >= 2) {
      // The Odometry's heading is the gyro's: no integration of the joints reproduces it.
      ds.odom_nominal = std::move(odom);
      ds.info.config[std::string(kOdometryHeading)] = "gyro";
      r.notes.push_back("the odometry is " + d.topics.at(Role::kOdom) +
                        " as logged: its heading is the integrated gyro (slamprep metadata)");
      return;
    }
    const SE2 start = odom.at(ds.encoders.front().stamp_s).value_or(SE2());
    ds.odom_nominal = integrateEncoders(ds.encoders, nominal, p.ticks_per_revolution, start);
    return;
  }
  if (odom.size() < 2) throw InputError(bag, d.topics.at(Role::kOdom) + ": fewer than 2 messages");
  const DiffDriveParams nominal = nominalGeometry(d, p, true, bag);
  double lateral = 0.0;
  ds.encoders = encodersFromPoses(odom, nominal, p.ticks_per_revolution, &lateral);
  ds.odom_nominal = std::move(odom);
  ds.info = importedInfo(
      p, nominal, bag, "mcap",
      "derived from Odometry " + d.topics.at(Role::kOdom) + " with the nominal geometry");
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

/// Scans whose time_increment --time-increment replaced, and those left at 0.
struct TimeIncrementCounts {
  std::size_t replaced = 0, zero = 0;
};

void applyTimeIncrement(LaserScan& scan, const ImportParams& p, TimeIncrementCounts& counts) {
  if (p.time_increment_s) {
    if (scan.time_increment_s != 0 && scan.time_increment_s != *p.time_increment_s)
      ++counts.replaced;
    scan.time_increment_s = *p.time_increment_s;
  }
  if (scan.time_increment_s == 0) ++counts.zero;
}

void addTimeIncrementNotes(const TimeIncrementCounts& c, std::size_t scans,
                           std::vector<std::string>& notes) {
  const std::string n = std::to_string(scans);
  if (c.replaced)
    notes.push_back("--time-increment replaced a different time_increment in " +
                    std::to_string(c.replaced) + " of " + n + " scans");
  if (c.zero)
    notes.push_back(std::to_string(c.zero) + " of " + n +
                    " scans have time_increment 0 (the bag does not say when each beam was "
                    "taken): de-skew methods will refuse them; give --time-increment SECONDS");
}

void setTimeIncrement(const ImportParams& p, ImportResult& r) {
  TimeIncrementCounts counts;
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
        params_(p) {}

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
  std::vector<std::string> files_;
  std::map<Role, std::string> topics_;
  PoseSeries odometry_;
  bool upside_down_ = false;
  ImportParams params_;
  TimeIncrementCounts counts_;
  std::size_t k_ = 0, count_ = 0, dropped_ = 0;
};

ImportResult importBag(const std::vector<ByteSource*>& files, const ImportParams& p,
                       const std::string& bag) {
  checkParams(p);
  if (p.base_frame.empty()) throw InputError("--base-frame", "must not be empty");
  std::unique_ptr<ScanSpill> spill;
  if (!p.spill_dir.empty()) spill = std::make_unique<ScanSpill>(p.spill_dir / kSpillFile);
  BagData d = readBag(files, p, bag, spill.get());
  ImportResult r;
  attachEncoders(d, p, bag, r);
  release(d.odom);  // what a long bag holds besides its scans: freed as soon as converted
  release(d.joints);
  Dataset& ds = r.dataset;
  std::vector<std::string> scan_where;
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
  mountLidar(d, p, r);
  const SE2& m = ds.info.T_base_lidar;
  if (!std::isfinite(m.x) || !std::isfinite(m.y) || !std::isfinite(m.yaw))
    throw InputError(bag, "lidar mount not finite");
  if (spill) {
    r.scans = std::make_unique<SpilledScans>(std::move(spill), d, ds, p);
    return r;
  }
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
