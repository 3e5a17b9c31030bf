// What real robots log besides clean data: cheap lidars (the beam count changing scan to scan,
// angle_min not 0, a range_max that is not the sensor's), odometry that holds a stale value while
// the robot moves and then catches up, twist samples no motion explains, and the --json summary.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>

#include "bag_writer.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/eval/formats/import.hpp"
#include "slamprep/eval/formats/import_json.hpp"
#include "slamprep/eval/formats/stale_odometry.hpp"
#include "slamprep/eval/formats/twist_spikes.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::eval {
namespace {
namespace fs = std::filesystem;

constexpr double kPi = std::numbers::pi;

/// Beams of scan s: 134 to 234, changing every scan.
std::size_t beamsOf(int s) {
  return 134 + (s * 37) % 101;
}

/// A range of beam i of scan s: 0.3 .. 3.5 m, a few no-returns (0).
float rangeOf(int s, std::size_t i) {
  return (i + s) % 17 == 0 ? 0.0f : float(0.3 + 3.2 * std::abs(std::sin(0.05 * i + s)));
}

struct RobotLog {
  double rate = 0.5;             ///< rad/s, the robot turning on the spot while driving
  double speed = 0.2;            ///< m/s
  int held_from = -1, held = 0;  ///< odometry samples [held_from, held_from + held] repeat
  bool standing_start = false;   ///< the first 10 samples: the robot stands
  bool joint_states = false;
  int twist_spike_at = -1;
};

SE2 truePose(double t) {  // an arc: constant speed and yaw rate from 10 s
  const double u = t - 10.0, w = 0.5, v = 0.2;
  return SE2(v / w * std::sin(w * u), v / w * (1 - std::cos(w * u)), w * u);
}

/// 4 s of a robot on an arc: Odometry at 50 Hz (maybe stale in places), optional JointState,
/// cheap-lidar scans at 5 Hz.
std::string robotLog(const RobotLog& p) {
  test::TestBag bag;
  for (int k = 0; k <= 200; ++k) {
    const double t = 10.0 + 0.02 * k;
    int source = k;
    if (p.held_from >= 0 && k > p.held_from && k <= p.held_from + p.held) source = p.held_from;
    const double ts =
        p.standing_start ? std::max(10.0 + 0.02 * source, 10.2) : 10.0 + 0.02 * source;
    const SE2 pose = truePose(ts);
    eval::OdometryMsg o;
    o.header = test::header(t, "odom");
    o.child_frame_id = "base_link";
    o.position = {pose.x, pose.y, 0.0};
    o.orientation = quaternionFromYaw(pose.yaw);
    o.linear[0] = 0.2;
    o.angular[2] = k == p.twist_spike_at ? 40.0 : 0.5;
    bag.add("/odom", kOdometryType, t, o);
    if (p.joint_states) {
      eval::JointStateMsg j;
      j.header = test::header(t, "base_link");
      j.name = {"wheel_left_joint", "wheel_right_joint"};
      const double u = ts - 10.0;  // r = 0.1, b = 0.5: left 0.75 rad/s, right 3.25 rad/s
      j.position = {0.75 * u, 3.25 * u};
      bag.add("/joint_states", kJointStateType, t, j);
    }
  }
  for (int s = 0; s < 18; ++s) {
    const double t = 10.25 + 0.2 * s;
    LaserScanMsg m;
    m.header = test::header(t, "base_link");
    m.angle_min = 0.01f;
    m.angle_increment = float(2 * kPi / 234);
    m.angle_max = m.angle_min + float(beamsOf(s) - 1) * m.angle_increment;
    m.time_increment = 4.4e-4f;
    m.scan_time = 0.2f;
    m.range_min = 0.12f;
    m.range_max = 100.0f;
    for (std::size_t i = 0; i < beamsOf(s); ++i) m.ranges.push_back(rangeOf(s, i));
    bag.add("/scan", kLaserScanType, t, m);
  }
  return bag.finish();
}

ImportParams params() {
  ImportParams p;
  p.nominal_geometry = DiffDriveParams{0.1, 0.1, 0.5};
  return p;
}

bool hasNote(const ImportResult& r, const std::string& text) {
  for (const auto& n : r.notes)
    if (n.find(text) != std::string::npos) return true;
  return false;
}

// import (spilled, as `slamprep import` does) -> dataset directory -> readDataset -> points.
TEST(CheapLidar, ScansWhoseBeamCountChangesGoEndToEnd) {
  const test::ScratchDir scratch("robot_log");
  const fs::path bag = scratch / "cheap.mcap", out = scratch / "dataset";
  writeFileAtomic(bag, robotLog({}));
  publishDirectoryAtomically(out, [&](const fs::path& partial) {
    ImportParams p = params();
    p.spill_dir = partial;
    ImportResult r = importRosbag2(bag, p);
    EXPECT_NE(r.summary.scans.find("134..228 beams"), std::string::npos) << r.summary.scans;
    // range_max 100 m while every reading is under 3.5 m: a note, recorded in the dataset.
    ASSERT_TRUE(r.summary.range);
    EXPECT_TRUE(r.summary.range->suspect);
    EXPECT_NEAR(r.summary.range->p999_m, 3.5, 0.011);
    EXPECT_TRUE(hasNote(r, "range_max 100 m is not the sensor's: readings reach 3.5"));
    EXPECT_TRUE(r.dataset.info.config.contains("range_max_suspect"));
    writeDatasetFiles(partial, r.dataset, out, [&](ScanRecord& s) { return r.scans->next(s); });
  });
  const Dataset d = readDataset(out);
  ASSERT_EQ(d.scans.size(), 18u);
  for (int s = 0; s < 18; ++s) {
    const LaserScan& scan = d.scans[s].scan;
    ASSERT_EQ(scan.size(), beamsOf(s)) << s;
    EXPECT_EQ(scan.angle_min_rad, double(0.01f));
    EXPECT_EQ(scan.time_increment_s, double(4.4e-4f));
    EXPECT_EQ(scan.range_max_m, 100.0);
    const Points2 points = scan.points();
    std::size_t returns = 0;
    for (std::size_t i = 0; i < scan.size(); ++i) returns += rangeOf(s, i) >= 0.12f;
    ASSERT_EQ(points.size(), returns) << s;
    // The first point is beam 0's, or beam 1's when beam 0 has no return.
    const std::size_t first = rangeOf(s, 0) >= 0.12f ? 0 : 1;
    const double r = rangeOf(s, first), a = scan.beamAngle(first);
    EXPECT_NEAR(points[0].x(), r * std::cos(a), 1e-6);
    EXPECT_NEAR(points[0].y(), r * std::sin(a), 1e-6);
  }
}

TEST(CheapLidar, MaxRangeMakesFartherReadingsNoReturn) {
  ImportParams p = params();
  p.max_range_m = 3.0;
  const ImportResult r = importMcap(robotLog({}), "cheap.mcap", p);
  std::size_t beyond = 0;
  for (int s = 0; s < 18; ++s)
    for (std::size_t i = 0; i < beamsOf(s); ++i) beyond += rangeOf(s, i) > 3.0f;
  ASSERT_GT(beyond, 100u);
  EXPECT_EQ(r.summary.range->cut, beyond);
  EXPECT_FALSE(r.summary.range->suspect);
  EXPECT_FALSE(hasNote(r, "is not the sensor's"));
  EXPECT_EQ(r.dataset.info.config.at("max_range_m"), 3.0);
  for (const auto& rec : r.dataset.scans) {
    EXPECT_EQ(rec.scan.range_max_m, 3.0);
    for (double range : rec.scan.ranges_m) EXPECT_TRUE(range <= 3.0 || std::isinf(range));
  }
}

// --reverse-beam-time: the same points (each beam keeps its direction), the array in reverse,
// so that beam i is the i-th taken; the stamp stays.
TEST(CheapLidar, ReversedBeamTimeKeepsEveryPointAndReversesTheOrder) {
  const ImportResult as_logged = importMcap(robotLog({}), "cheap.mcap", params());
  ImportParams p = params();
  p.reverse_beam_time = true;
  const ImportResult reversed = importMcap(robotLog({}), "cheap.mcap", p);
  ASSERT_EQ(as_logged.dataset.scans.size(), reversed.dataset.scans.size());
  for (std::size_t k = 0; k < reversed.dataset.scans.size(); ++k) {
    const LaserScan& a = as_logged.dataset.scans[k].scan;
    const LaserScan& b = reversed.dataset.scans[k].scan;
    ASSERT_EQ(a.size(), b.size());
    EXPECT_EQ(b.stamp_s, a.stamp_s);
    EXPECT_EQ(b.angle_increment_rad, -a.angle_increment_rad);
    for (std::size_t i = 0; i < a.size(); ++i) {
      const std::size_t j = a.size() - 1 - i;
      EXPECT_EQ(b.ranges_m[j], a.ranges_m[i]);
      EXPECT_NEAR(b.beamAngle(j), a.beamAngle(i), 1e-9);
    }
  }
}

TEST(StaleOdometry, AHeldPoseFollowedByAJumpIsDroppedAndInterpolatedOver) {
  RobotLog log;
  log.held_from = 100;  // 12 s: five samples repeat sample 100, then 106 catches up
  log.held = 5;
  const ImportResult r = importMcap(robotLog(log), "stale.mcap", params());
  ASSERT_EQ(r.summary.stale.size(), 1u);
  const StaleReport& s = r.summary.stale[0];
  ASSERT_EQ(s.runs.size(), 1u);
  EXPECT_EQ(s.dropped(), 5u);
  EXPECT_EQ(s.runs[0].first, 100u);
  EXPECT_NEAR(s.runs[0].span_s, 0.12, 1e-9);
  EXPECT_NEAR(s.runs[0].jump[1], 0.06, 1e-9);  // 6 periods at 0.5 rad/s
  EXPECT_EQ(r.dataset.odom_nominal.size(), 196u);
  // Interpolated over the gap the pose is the arc's (geodesic on a constant twist: exact).
  const SE2 mid = *r.dataset.odom_nominal.at(12.05);
  EXPECT_NEAR(mid.yaw, truePose(12.05).yaw, 1e-9);
  EXPECT_NEAR(mid.x, truePose(12.05).x, 1e-9);
  EXPECT_NE(s.text().find("1 stale runs, 5 of 201 samples dropped"), std::string::npos) << s.text();
}

TEST(StaleOdometry, ARobotStandingStillIsNotStale) {
  RobotLog log;
  log.standing_start = true;  // the first 11 samples repeat (robot at rest), then it drives
  const ImportResult r = importMcap(robotLog(log), "stand.mcap", params());
  ASSERT_EQ(r.summary.stale.size(), 1u);
  EXPECT_TRUE(r.summary.stale[0].runs.empty());
  EXPECT_EQ(r.summary.stale[0].repeated_runs, 1u);
  EXPECT_EQ(r.dataset.odom_nominal.size(), 201u);
}

TEST(StaleOdometry, AFrozenJointStreamIsDroppedAndTheLoggedOdometryKept) {
  RobotLog log;
  log.joint_states = true;
  log.held_from = 50;
  log.held = 4;
  const ImportResult r = importMcap(robotLog(log), "joints.mcap", params());
  ASSERT_EQ(r.summary.stale.size(), 2u);  // Odometry and JointState, both frozen
  EXPECT_EQ(r.summary.stale[1].stream, "JointState /joint_states");
  EXPECT_EQ(r.summary.stale[1].dropped(), 4u);
  EXPECT_EQ(r.dataset.encoders.size(), 197u);
  EXPECT_EQ(r.dataset.info.config.at("encoders_from"), "joint_states");
  EXPECT_EQ(r.dataset.odometry_logged.size(), 197u);
  // The encoders re-integrated (r 0.1, b 0.5) follow the arc over the gap.
  EXPECT_NEAR(r.dataset.odom_nominal.at(11.05)->yaw, truePose(11.05).yaw, 1e-5);
}

TEST(StaleOdometry, CarmenOdometryIsCheckedToo) {
  // ODOM at 10 Hz turning at 0.5 rad/s; lines 31..35 repeat line 30, then 36 catches up.
  std::string log;
  for (int k = 0; k <= 60; ++k) {
    const int source = k > 30 && k <= 35 ? 30 : k;
    const SE2 pose = truePose(10.0 + 0.1 * source);
    const std::string t = std::to_string(100.0 + 0.1 * k);
    log += "ODOM " + std::to_string(pose.x) + " " + std::to_string(pose.y) + " " +
           std::to_string(pose.yaw) + " 0 0 0 " + t + " host " + t + "\n";
    if (k % 5 == 2) log += "FLASER 3 1.0 2.0 3.0 0 0 0 0 0 0 " + t + " host " + t + "\n";
  }
  const ImportResult r = importCarmen(log, "stale.clf", params());
  ASSERT_EQ(r.summary.stale.size(), 1u);
  EXPECT_EQ(r.summary.stale[0].dropped(), 5u);
  EXPECT_EQ(r.dataset.odom_nominal.size(), 56u);
}

TEST(StaleOdometry, TheRuleOnSamplesDirectly) {
  // 10 Hz turning 0.3 rad/s; five samples held, then a catch-up; later a standing robot.
  PoseSeries poses;
  double yaw = 0.0;
  for (int k = 0; k < 100; ++k) {
    if (k < 40 || k > 45) yaw = 0.03 * std::min(k, 70);
    poses.push_back(0.1 * k, SE2(0, 0, yaw));
  }
  StaleReport report;
  const PoseSeries kept = dropStaleOdometry(poses, report);
  ASSERT_EQ(report.runs.size(), 1u);  // 40..45 stale; 70..99 standing at the end: kept
  EXPECT_EQ(report.runs[0].first, 39u);
  EXPECT_EQ(report.dropped(), 6u);
  EXPECT_EQ(report.repeated_runs, 2u);
  EXPECT_EQ(kept.size(), 94u);
  EXPECT_NEAR(report.threshold[1], 3 * 0.1 * 0.3, 1e-9);
  // Encoders: the same rule on wheel angles.
  EncoderLog enc;
  for (int k = 0; k < 100; ++k) {
    const int held = k > 20 && k <= 24 ? 20 : k;
    enc.push_back({0.01 * k, 1000 * held, 2000 * held});
  }
  StaleReport er;
  EXPECT_EQ(dropStaleEncoders(enc, 1e-4, er).size(), 96u);
}

TEST(TwistSpikes, AnAbsurdYawRateThePosesDoNotShowIsCounted) {
  RobotLog log;
  log.twist_spike_at = 77;
  const ImportResult r = importMcap(robotLog(log), "twist.mcap", params());
  ASSERT_TRUE(r.summary.twist_spikes);
  const TwistSpikeReport& t = *r.summary.twist_spikes;
  EXPECT_EQ(t.angular.count, 1u);
  EXPECT_EQ(t.angular.largest, 40.0);
  EXPECT_NEAR(t.angular.largest_at_s, 11.54, 1e-9);
  EXPECT_NEAR(t.angular.derived_there, 0.5, 1e-6);
  EXPECT_EQ(t.linear.count, 0u);
  const ImportResult clean = importMcap(robotLog({}), "twist.mcap", params());
  EXPECT_EQ(clean.summary.twist_spikes->angular.count, 0u);
}

TEST(ImportJson, TheSummaryHasEveryKeyAndTheSensorAgreementPlaceholder) {
  RobotLog log;
  log.held_from = 100;
  log.held = 5;
  const ImportResult r = importMcap(robotLog(log), "stale.mcap", params());
  const auto j = importSummaryJson("stale.mcap", "rosbag2", "out", r.summary, r.dataset,
                                   {r.dataset.scans.size()}, r.notes);
  EXPECT_TRUE(j.at("sensor_agreement").is_null());
  EXPECT_EQ(j.at("counts").at("scans"), 18u);
  EXPECT_EQ(j.at("topics").at("sensor_msgs/msg/LaserScan"), "/scan");
  EXPECT_EQ(j.at("stale_odometry").at(0).at("stale_runs"), 1u);
  EXPECT_NEAR(j.at("stale_odometry").at(0).at("longest_span_s").get<double>(), 0.12, 1e-9);
  EXPECT_EQ(j.at("max_range").at("range_max_suspect"), true);
  EXPECT_EQ(j.at("twist_spikes").at("angular_z_rad_s").at("count"), 0u);
  EXPECT_EQ(j.at("encoders_from"), "odometry_poses");
  EXPECT_EQ(j.at("lidar_mount").at("x_m"), 0.0);
}

}  // namespace
}  // namespace slamprep::eval
