// The MCAP (ROS 2 bag) export, laid out as REP 105 says a robot publishes: odom -> base_link on
// /tf and /odom from the wheel odometry, base_link -> laser on /tf_static, and the ground truth
// on its own topic, never in the tf tree (docs/export.md, "MCAP").
#include <unistd.h>

#include <algorithm>
#include <deque>
#include <fstream>
#include <functional>
#include <limits>
#include <queue>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/core/partial_cleanup.hpp"
#include "slamprep/eval/formats/export.hpp"
#include "slamprep/eval/formats/mcap.hpp"
#include "slamprep/eval/formats/ros2_messages.hpp"
#include "slamprep/eval/formats/rosbag2.hpp"
#include "slamprep/eval/formats/text_io.hpp"

namespace slamprep::eval {
namespace {

constexpr double kStandardGravity_mps2 = 9.80665;

// rosbag2's offered_qos_profiles (Humble YAML, enum values: history 1 keep_last, reliability 1
// reliable, durability 1 transient_local / 2 volatile, liveliness 1 automatic).
std::string qosYaml(bool latched) {
  const std::string infinite = "\n    sec: 2147483647\n    nsec: 4294967295";
  return std::string("- history: 1\n  depth: ") + (latched ? "1" : "100") +
         "\n  reliability: 1\n  durability: " + (latched ? "1" : "2") + "\n  deadline:" + infinite +
         "\n  lifespan:" + infinite + "\n  liveliness: 1\n  liveliness_lease_duration:" + infinite +
         "\n  avoid_ros_namespace_conventions: false\n";
}

std::uint64_t logTimeNs(double stamp_s, const std::string& where) {
  const RosTime t = rosTimeFromSeconds(stamp_s, where);
  if (t.nanoseconds() < 0)
    throw InputError(where, "negative stamp " + std::to_string(stamp_s) +
                                " s: MCAP log times are unsigned nanoseconds");
  return static_cast<std::uint64_t>(t.nanoseconds());
}

LaserScanMsg laserScanMsg(const LaserScan& s, const std::string& frame, const std::string& where) {
  LaserScanMsg m;
  m.header = {rosTimeFromSeconds(s.stamp_s, where), frame};
  m.angle_min = static_cast<float>(s.angle_min_rad);
  m.angle_max = static_cast<float>(s.size() == 0 ? s.angle_min_rad : s.beamAngle(s.size() - 1));
  m.angle_increment = static_cast<float>(s.angle_increment_rad);
  m.time_increment = static_cast<float>(s.time_increment_s);
  m.scan_time = static_cast<float>(s.scan_time_s);
  m.range_min = static_cast<float>(s.range_min_m);
  m.range_max = static_cast<float>(s.range_max_m);
  m.ranges.reserve(s.size());
  for (double r : s.ranges_m) m.ranges.push_back(static_cast<float>(r));
  return m;
}

OdometryMsg odometryMsg(const PoseSeries& poses, std::size_t k, const std::string& parent,
                        const std::string& child, const std::string& where) {
  OdometryMsg m;
  m.header = {rosTimeFromSeconds(poses[k].stamp_s, where), parent};
  m.child_frame_id = child;
  const SE2& T = poses[k].value;
  m.position = {T.x, T.y, 0.0};
  m.orientation = quaternionFromYaw(T.yaw);
  const Eigen::Vector3d xi = twistAt(poses, k);
  m.linear = {xi.x(), xi.y(), 0.0};
  m.angular = {0.0, 0.0, xi.z()};
  return m;
}

TfMsg tfMsg(double stamp_s, const std::string& parent, const std::string& child, const SE2& T,
            const std::string& where) {
  TransformStampedMsg t;
  t.header = {rosTimeFromSeconds(stamp_s, where), parent};
  t.child_frame_id = child;
  t.translation = {T.x, T.y, 0.0};
  t.rotation = quaternionFromYaw(T.yaw);
  return {{t}};
}

/// One topic's messages, encoded on demand in log-time order, so the merge of all topics holds
/// one encoded message at a time, not the bag.
struct TopicStream {
  std::uint16_t channel = 0;
  std::vector<std::uint64_t> log_ns;               ///< of message k
  std::vector<std::size_t> order;                  ///< message indices by log time (stable)
  std::function<std::string(std::size_t)> encode;  ///< CDR of message k
};

class BagBuilder {
 public:
  explicit BagBuilder(McapWriter& writer) : writer_(writer) {}

  /// A channel (its schema added once) and its stream of `n` messages.
  TopicStream& topic(std::string_view type, const std::string& name, bool latched = false) {
    auto it = schema_ids_.find(std::string(type));
    if (it == schema_ids_.end())
      it = schema_ids_
               .emplace(std::string(type),
                        writer_.addSchema(std::string(type), "ros2msg", ros2MsgSchema(type)))
               .first;
    TopicStream s;
    s.channel =
        writer_.addChannel(it->second, name, "cdr", {{"offered_qos_profiles", qosYaml(latched)}});
    topics_.push_back(name);
    streams_.push_back(std::move(s));
    return streams_.back();
  }

  /// Messages of every stream, merged by log time (ties: stream, then message order, as a
  /// stable sort of all of them would put them), after the latched /tf_static mount.
  void write(const std::function<std::string(std::uint64_t)>& tf_static,
             std::map<std::string, std::size_t>* counts) {
    using Head = std::pair<std::uint64_t, std::size_t>;  // log time, stream
    std::priority_queue<Head, std::vector<Head>, std::greater<>> heads;
    std::vector<std::size_t> next(streams_.size(), 0);
    std::uint64_t t0 = std::numeric_limits<std::uint64_t>::max();
    for (std::size_t i = 0; i < streams_.size(); ++i) {
      TopicStream& s = streams_[i];
      s.order.resize(s.log_ns.size());
      for (std::size_t k = 0; k < s.order.size(); ++k) s.order[k] = k;
      std::stable_sort(s.order.begin(), s.order.end(),
                       [&](std::size_t a, std::size_t b) { return s.log_ns[a] < s.log_ns[b]; });
      if (!s.order.empty()) {
        heads.push({s.log_ns[s.order[0]], i});
        t0 = std::min(t0, s.log_ns[s.order[0]]);
      }
    }
    if (heads.empty()) t0 = 0;
    // The static mount first of all, at the earliest time in the bag.
    const auto static_ch = topic(kTfType, "/tf_static", true).channel;
    writer_.addMessage(static_ch, t0, t0, tf_static(t0));
    while (!heads.empty()) {
      const auto [t, i] = heads.top();
      heads.pop();
      const TopicStream& s = streams_[i];
      writer_.addMessage(s.channel, t, t, s.encode(s.order[next[i]]));
      if (++next[i] < s.order.size()) heads.push({s.log_ns[s.order[next[i]]], i});
    }
    if (counts) {
      counts->clear();
      for (std::size_t i = 0; i < streams_.size(); ++i)
        (*counts)[topics_[i]] = streams_[i].log_ns.size();
      (*counts)["/tf_static"] = 1;
    }
  }

 private:
  McapWriter& writer_;
  std::map<std::string, std::uint16_t> schema_ids_;
  std::vector<std::string> topics_;
  std::deque<TopicStream> streams_;  // stable references while topics are added
};

/// "file:line", the place a message's values come from (for errors).
std::string line(const char* file, std::size_t k) {
  std::string s(file);
  s += ':';
  s += std::to_string(k);
  return s;
}

void addScans(BagBuilder& bag, const std::vector<ScanRecord>& scans, const std::string& topic,
              const std::string& file, const ExportParams& p) {
  TopicStream& s = bag.topic(kLaserScanType, topic);
  for (std::size_t i = 0; i < scans.size(); ++i)
    // Logged when the last beam is in: a consumer has the odometry that covers the scan before
    // the scan itself (docs/export.md).
    s.log_ns.push_back(logTimeNs(scans[i].scan.endTime(), line(file.c_str(), i + 1)));
  s.encode = [&scans, file, &p](std::size_t i) {
    return encodeCdr(laserScanMsg(scans[i].scan, p.laser_frame, line(file.c_str(), i + 1)));
  };
}

/// nav_msgs/Odometry of `poses` (parent -> child), and, with `tf`, the same poses on /tf.
void addOdometry(BagBuilder& bag, const PoseSeries& poses, const std::string& topic,
                 const char* file, const std::string& parent, const std::string& child) {
  TopicStream& s = bag.topic(kOdometryType, topic);
  for (std::size_t k = 0; k < poses.size(); ++k)
    s.log_ns.push_back(logTimeNs(poses[k].stamp_s, line(file, k + 2)));
  s.encode = [&poses, file, &parent, &child](std::size_t k) {
    return encodeCdr(odometryMsg(poses, k, parent, child, line(file, k + 2)));
  };
}

void addTf(BagBuilder& bag, const PoseSeries& poses, const char* file, const ExportParams& p) {
  TopicStream& s = bag.topic(kTfType, "/tf");
  for (std::size_t k = 0; k < poses.size(); ++k)
    s.log_ns.push_back(logTimeNs(poses[k].stamp_s, line(file, k + 2)));
  s.encode = [&poses, file, &p](std::size_t k) {
    return encodeCdr(
        tfMsg(poses[k].stamp_s, p.odom_frame, p.base_frame, poses[k].value, line(file, k + 2)));
  };
}

void addImu(BagBuilder& bag, const ImuLog& imu, const ExportParams& p) {
  TopicStream& s = bag.topic(kImuType, "/imu");
  for (std::size_t k = 0; k < imu.size(); ++k)
    s.log_ns.push_back(logTimeNs(imu[k].stamp_s, line("imu.csv", k + 2)));
  s.encode = [&imu, &p](std::size_t k) {
    ImuMsg m;
    m.header = {rosTimeFromSeconds(imu[k].stamp_s, line("imu.csv", k + 2)), p.base_frame};
    m.orientation_covariance[0] = -1.0;  // REP 145: no orientation estimate
    m.angular_velocity = {0.0, 0.0, imu[k].gyro_z_radps};
    // Planar robot on level ground: the z specific force is +g.
    m.linear_acceleration = {imu[k].accel_x_mps2, imu[k].accel_y_mps2, kStandardGravity_mps2};
    return encodeCdr(m);
  };
}

void addJoints(BagBuilder& bag, const Dataset& d, const ExportParams& p) {
  TopicStream& s = bag.topic(kJointStateType, "/joint_states");
  for (std::size_t k = 0; k < d.encoders.size(); ++k)
    s.log_ns.push_back(logTimeNs(d.encoders[k].stamp_s, line("encoders.csv", k + 2)));
  const double rad_per_tick = radiansPerTick(d.info.ticks_per_revolution);
  s.encode = [&d, &p, rad_per_tick](std::size_t k) {
    const EncoderSample& e = d.encoders[k];
    JointStateMsg m;
    m.header = {rosTimeFromSeconds(e.stamp_s, line("encoders.csv", k + 2)), p.base_frame};
    m.name = {"wheel_left_joint", "wheel_right_joint"};
    m.position = {double(e.ticks_left) * rad_per_tick, double(e.ticks_right) * rad_per_tick};
    return encodeCdr(m);
  };
}

std::string decimal(double v) {
  std::string s;
  appendDouble(s, v);
  return s;
}

void writeBag(const ExportInput& input, const ExportParams& p, McapWriter& writer,
              std::map<std::string, std::size_t>* counts) {
  const Dataset& d = input.dataset;
  const DiffDriveParams& g = d.info.nominal_geometry;
  // What a bag cannot otherwise carry, so `slamprep import` needs no --nominal for it, and
  // keeps an odometry whose heading is the gyro's instead of integrating the joints.
  std::vector<std::pair<std::string, std::string>> metadata = {
      {std::string(kNominalRadiusLeft), decimal(g.radius_left_m)},
      {std::string(kNominalRadiusRight), decimal(g.radius_right_m)},
      {std::string(kNominalWheelBase), decimal(g.wheel_base_m)}};
  if (d.info.config.value(std::string(kOdometryHeading), "") == "gyro")
    metadata.emplace_back(kOdometryHeading, "gyro");
  writer.addMetadata(std::string(kSlamprepMetadata), std::move(metadata));
  BagBuilder bag(writer);
  addScans(bag, d.scans, "/scan", "scans.jsonl", p);
  for (const auto& [method, scans] : input.deskewed)
    addScans(bag, scans, "/scan_deskewed/" + method, "deskewed_" + method + ".jsonl", p);
  PoseSeries calibrated;
  if (input.calibration) calibrated = calibratedOdometry(input);
  if (!d.odom_nominal.empty())
    addOdometry(bag, d.odom_nominal, "/odom", "odom_nominal.tum", p.odom_frame, p.base_frame);
  if (input.calibration)
    addOdometry(bag, calibrated, "/odom_calibrated", "encoders.csv", p.odom_frame, p.base_frame);
  if (!d.imu.empty()) addImu(bag, d.imu, p);
  if (!d.encoders.empty()) addJoints(bag, d, p);
  if (!d.odom_nominal.empty()) addTf(bag, d.odom_nominal, "odom_nominal.tum", p);
  if (d.hasTruth())
    addOdometry(bag, d.groundtruth, "/ground_truth", "groundtruth.tum", p.world_frame,
                p.base_frame);
  bag.write(
      [&](std::uint64_t t0) {
        TfMsg m = tfMsg(0.0, p.base_frame, p.laser_frame, d.info.T_base_lidar, "dataset.json");
        m.transforms[0].header.stamp = rosTimeFromNanoseconds(static_cast<std::int64_t>(t0));
        return encodeCdr(m);
      },
      counts);
}

McapWriterParams writerParams(const ExportParams& p) {
  McapWriterParams wp;
  wp.chunk_size_bytes = p.mcap_chunk_size_bytes;
  wp.compression = p.mcap_compression;
  return wp;
}

}  // namespace

Eigen::Vector3d twistAt(const PoseSeries& poses, std::size_t k) {
  if (k == 0 || poses.size() < 2) return Eigen::Vector3d::Zero();
  const double dt = poses[k].stamp_s - poses[k - 1].stamp_s;
  return between(poses[k - 1].value, poses[k].value).log() / dt;
}

std::string formatMcap(const ExportInput& input, const ExportParams& p,
                       std::map<std::string, std::size_t>* counts) {
  McapWriter writer(writerParams(p));
  writeBag(input, p, writer, counts);
  return writer.finish();
}

void writeMcapFile(const std::filesystem::path& file, const ExportInput& input,
                   const ExportParams& p, std::map<std::string, std::size_t>* counts) {
  std::error_code ec;
  if (file.has_parent_path()) std::filesystem::create_directories(file.parent_path(), ec);
  const std::filesystem::path tmp = partialSibling(file);
  const PartialInFlight in_flight(tmp);  // removed if a signal ends the process
  try {
    {
      std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
      McapWriter writer(writerParams(p), &out);
      writeBag(input, p, writer, counts);
      writer.finish();
      out.flush();
      if (!out) throw InputError(file.string(), "cannot write file");
    }
    renameIntoPlace(tmp, file);
  } catch (...) {
    std::filesystem::remove(tmp, ec);
    throw;
  }
}

}  // namespace slamprep::eval
