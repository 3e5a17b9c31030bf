// Import: a hand-written CARMEN log and an MCAP bag written by the independent @mcap/core writer
// become datasets that readDataset accepts; the exporter's own bag round-trips.
#include "slamprep/eval/formats/import.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "node_tool.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/eval/formats/export.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"
#include "synthetic_dataset.hpp"

namespace slamprep::eval {
namespace {
namespace fs = std::filesystem;

// 4 ODOM lines along x with a turn, 2 scans inside them; laser 0.15 m ahead of the base.
const char* kImportLog =
    "ODOM 1 2 0 0 0 0 100.0 host 100.0\n"
    "ROBOTLASER1 0 -1.5707963267948966 3.141592653589793 0.7853981633974483 20 0.01 0 5 "
    "1.0 2.0 20 3.0 4.5 0 1.2 2 0 1.05 2 0 0.5 0 0 0 0 100.1 host 100.1\n"
    "ODOM 1.1 2 0 0.5 0 0 100.2 host 100.2\n"
    "ODOM 1.2 2.01 0.1 0.5 0.5 0 100.4 host 100.4\n"
    "ROBOTLASER1 0 -1.5707963267948966 3.141592653589793 0.7853981633974483 20 0.01 0 5 "
    "1.5 2.5 3.5 20 5.5 0 1.4 2.02 0.1 1.25 2.02 0.1 0.5 0 0 0 0 100.5 host 100.5\n"
    "ODOM 1.3 2.03 0.2 0.5 0.5 0 100.6 host 100.6\n";

TEST(ImportCarmen, HandWrittenLogBecomesADatasetThatReadsBack) {
  ImportParams p;
  p.time_increment_s = 1e-3;
  p.nominal_geometry = DiffDriveParams{0.1, 0.1, 0.5};
  p.lidar_mount_from_poses = true;  // the log has no mount PARAM
  const ImportResult r = importCarmen(kImportLog, "run.clf", p);
  const Dataset& d = r.dataset;
  ASSERT_EQ(d.scans.size(), 2u);
  EXPECT_EQ(d.odom_nominal.size(), 4u);
  EXPECT_FALSE(d.hasTruth());
  EXPECT_NEAR(d.info.T_base_lidar.x, 0.15, 1e-12);
  EXPECT_NEAR(d.info.T_base_lidar.y, 0.0, 1e-12);
  EXPECT_NE(r.summary.lidar_mount.find("--lidar-mount-from-poses"), std::string::npos);
  EXPECT_EQ(d.scans[1].scan.stamp_s, 100.5);
  EXPECT_EQ(d.scans[1].scan.time_increment_s, 1e-3);
  EXPECT_NEAR(d.scans[1].scan.scan_time_s, 0.4, 1e-12);  // the median stamp spacing
  EXPECT_TRUE(std::isinf(d.scans[0].scan.ranges_m[2]));
  // The derived encoders reproduce the logged odometry: 2^20 ticks per revolution round each
  // wheel angle to 3e-6 rad (0.3 um on a 0.1 m wheel); the poses here have no sideways steps
  // beyond the first-order arc, so re-integration lands within 1e-5 m and rad.
  const PoseSeries again = integrateEncoders(d.encoders, d.info.nominal_geometry,
                                             d.info.ticks_per_revolution, d.odom_nominal[0].value);
  for (std::size_t k = 0; k < again.size(); ++k) {
    EXPECT_NEAR(again[k].value.x, d.odom_nominal[k].value.x, 1e-3) << k;
    EXPECT_NEAR(again[k].value.yaw, d.odom_nominal[k].value.yaw, 1e-5) << k;
  }
  const test::ScratchDir scratch("import");
  const fs::path dir = scratch / "carmen_ds";
  writeDataset(dir, d);
  const Dataset back = readDataset(dir);
  EXPECT_EQ(back.scans.size(), 2u);
  EXPECT_EQ(back.encoders.size(), 4u);
}

// Every laser line 0.15 m ahead of its robot pose, in the robot's frame: one configured offset
// (CARMEN writes laser_pose as robot_pose * its front laser offset), taken as the mount.
TEST(ImportCarmen, TheMountIsTheLinesOffsetWhereEveryLineHasTheSame) {
  std::string log = kImportLog;
  const std::string logged = "1.4 2.02 0.1 1.25 2.02 0.1";
  const std::string ahead = "1.3992504164 2.0349750208 0.1 1.25 2.02 0.1";  // 0.15 along 0.1 rad
  log.replace(log.find(logged), logged.size(), ahead);
  const ImportResult r = importCarmen(log, "run.clf");
  EXPECT_NEAR(r.dataset.info.T_base_lidar.x, 0.15, 1e-9);
  EXPECT_NEAR(r.dataset.info.T_base_lidar.y, 0.0, 1e-9);
  EXPECT_NE(r.summary.lidar_mount.find("the same on every ROBOTLASER1 line"), std::string::npos)
      << r.summary.lidar_mount;
  for (const auto& note : r.notes) EXPECT_EQ(note.find("laser_pose"), std::string::npos) << note;
}

// Offsets that differ from line to line (here by 1.5 cm: the second line's laser is 0.15 m
// ahead in x of the world, not of the robot turned by 0.1 rad) are two pose estimates, not a
// calibration: identity, and the disagreement said.
TEST(ImportCarmen, TheMountIsNotTakenFromPosesThatDisagreeUnlessAsked) {
  const ImportResult r = importCarmen(kImportLog, "run.clf");
  EXPECT_EQ(r.dataset.info.T_base_lidar.x, 0.0);
  EXPECT_EQ(r.dataset.info.T_base_lidar.yaw, 0.0);
  EXPECT_NE(r.summary.lidar_mount.find("identity used"), std::string::npos)
      << r.summary.lidar_mount;
  // The disagreement with the logged poses is reported, not silently adopted.
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_NE(r.notes[0].find("differs from robot_pose * mount by up to 0.15 m"), std::string::npos)
      << r.notes[0];
  // Without a nominal geometry no encoder ticks are made up.
  EXPECT_TRUE(r.dataset.encoders.empty());
  EXPECT_EQ(r.dataset.info.config["nominal_geometry_from"], "absent");
  EXPECT_EQ(r.summary.nominal_geometry.rfind("absent", 0), 0u);
  // --lidar-mount wins over everything.
  ImportParams p;
  p.T_base_lidar = SE2(0.1, 0.02, 0.5);
  p.lidar_mount_from_poses = true;
  EXPECT_EQ(importCarmen(kImportLog, "run.clf", p).dataset.info.T_base_lidar.y, 0.02);
}

TEST(ImportCarmen, ScansOutsideTheOdometryAreRefusedOrTrimmed) {
  const std::string log = std::string(kImportLog) +
                          "ROBOTLASER1 0 -1.5707963267948966 3.141592653589793 "
                          "0.7853981633974483 20 0.01 0 5 1 1 1 1 1 0 0 0 0 0 0 0 0 0 0 0 0 "
                          "101 host 101\n";
  ImportParams strict;
  strict.trim = false;  // --no-trim
  try {
    importCarmen(log, "run.clf", strict);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("run.clf:7: scan at 101"), std::string::npos) << e.what();
  }
  const ImportResult trimmed = importCarmen(log, "run.clf");  // the default drops it
  EXPECT_EQ(trimmed.dataset.scans.size(), 2u);
  const std::string notes = ::testing::PrintToString(trimmed.notes);
  EXPECT_NE(notes.find("1 scans outside the odometry (before its first sample or after its last) "
                       "were dropped"),
            std::string::npos)
      << notes;
  EXPECT_THROW(importCarmen("ODOM 0 0 0 0 0 0 1 h 1\n", "x.clf"), InputError);  // no laser
}

TEST(ImportCarmen, ExportedLogCarriesGeometryAndTimingSoTheDatasetComesBack) {
  const Dataset d = test::makeSyntheticDataset();
  const ImportResult r = importCarmen(formatCarmen(d, d.scans, {}), "x.clf");
  EXPECT_EQ(r.dataset.info.nominal_geometry.radius_left_m, d.info.nominal_geometry.radius_left_m);
  EXPECT_EQ(r.dataset.info.nominal_geometry.wheel_base_m, d.info.nominal_geometry.wheel_base_m);
  ASSERT_EQ(r.dataset.scans.size(), d.scans.size());
  EXPECT_EQ(r.dataset.scans[3].scan.time_increment_s, d.scans[3].scan.time_increment_s);
  EXPECT_NEAR(r.dataset.info.T_base_lidar.y, d.info.T_base_lidar.y, 1e-12);
  // The whole mount comes back from the PARAM lines, exactly, and agrees with the laser poses.
  EXPECT_EQ(r.dataset.info.T_base_lidar.x, d.info.T_base_lidar.x);
  EXPECT_EQ(r.dataset.info.T_base_lidar.yaw, d.info.T_base_lidar.yaw);
  EXPECT_NE(r.summary.lidar_mount.find("PARAM robot_frontlaser_offset, _side_offset, "
                                       "_angular_offset"),
            std::string::npos)
      << r.summary.lidar_mount;
  for (const auto& note : r.notes) EXPECT_EQ(note.find("laser_pose"), std::string::npos) << note;
  // The encoders derived from the nominal odometry with the nominal geometry are the original
  // ticks at 2^20 / 4096 = 256 times the resolution: inverting the arc model loses ~1e-12 rad,
  // far below half a tick (3e-6 rad), so they are exact.
  ASSERT_EQ(r.dataset.encoders.size(), d.encoders.size());
  for (std::size_t k = 0; k < d.encoders.size(); ++k) {
    ASSERT_EQ(r.dataset.encoders[k].ticks_left, 256 * d.encoders[k].ticks_left) << k;
    ASSERT_EQ(r.dataset.encoders[k].ticks_right, 256 * d.encoders[k].ticks_right) << k;
  }
}

nlohmann::json stamp(double t) {
  const auto sec = static_cast<std::int64_t>(std::floor(t));
  return {{"sec", sec}, {"nanosec", std::llround((t - sec) * 1e9)}};
}

std::int64_t stampNs(double t) {
  const auto sec = static_cast<std::int64_t>(std::floor(t));
  return sec * 1000000000 + std::llround((t - sec) * 1e9);
}

TEST(ImportMcap, BagWrittenByTheIndependentWriterBecomesADataset) {
  SLAMPREP_REQUIRE_NODE_TOOL();
  nlohmann::json spec;
  spec["channels"] = {{{"topic", "/front/scan"}, {"type", "sensor_msgs/msg/LaserScan"}},
                      {{"topic", "/wheels"}, {"type", "sensor_msgs/msg/JointState"}},
                      {{"topic", "/odom"}, {"type", "nav_msgs/msg/Odometry"}}};
  nlohmann::json messages = nlohmann::json::array();
  // Joints at 20 Hz from 9.9 s to 10.5 s; the left wheel turns 1 rad/s, the right 2 rad/s.
  for (int k = 0; k <= 12; ++k) {
    const double t = 9.9 + 0.05 * k;
    messages.push_back({{"topic", "/wheels"},
                        {"log_time", stampNs(t)},
                        {"msg",
                         {{"header", {{"stamp", stamp(t)}, {"frame_id", "base"}}},
                          {"name", {"caster", "right_wheel", "left_wheel"}},
                          {"position", {0.0, 2.0 * (t - 9.9), 1.0 * (t - 9.9)}},
                          {"velocity", nlohmann::json::array()},
                          {"effort", nlohmann::json::array()}}}});
    messages.push_back({{"topic", "/odom"},
                        {"log_time", stampNs(t)},
                        {"msg",
                         {{"header", {{"stamp", stamp(t)}, {"frame_id", "odom"}}},
                          {"child_frame_id", "base"},
                          {"pose",
                           {{"pose",
                             {{"position", {{"x", t}, {"y", 0}, {"z", 0}}},
                              {"orientation", {{"x", 0}, {"y", 0}, {"z", 0}, {"w", 1}}}}},
                            {"covariance", std::vector<double>(36, 0.0)}}},
                          {"twist",
                           {{"twist",
                             {{"linear", {{"x", 0}, {"y", 0}, {"z", 0}}},
                              {"angular", {{"x", 0}, {"y", 0}, {"z", 0}}}}},
                            {"covariance", std::vector<double>(36, 0.0)}}}}}});
  }
  for (int s = 0; s < 3; ++s) {
    const double t = 10.0 + 0.1 * s;
    messages.push_back({{"topic", "/front/scan"},
                        {"log_time", stampNs(t + 0.09)},
                        {"msg",
                         {{"header", {{"stamp", stamp(t)}, {"frame_id", "front_laser"}}},
                          {"angle_min", -1.0},
                          {"angle_max", 1.0},
                          {"angle_increment", 0.5},
                          {"time_increment", 0.0225},
                          {"scan_time", 0.1},
                          {"range_min", 0.1},
                          {"range_max", 12.0},
                          {"ranges", {1.5, 2.25, 3.0 + s, 0.0625, 100.0}},
                          {"intensities", nlohmann::json::array()}}}});
  }
  std::stable_sort(messages.begin(), messages.end(), [](const auto& a, const auto& b) {
    return a["log_time"].template get<std::int64_t>() < b["log_time"].template get<std::int64_t>();
  });
  spec["messages"] = messages;
  const test::ScratchDir scratch("import");
  const fs::path spec_file = scratch / "spec.json", bag = scratch / "node.mcap";
  writeFileAtomic(spec_file, spec.dump());
  std::string log;
  ASSERT_EQ(test::runNodeTool("write '" + spec_file.string() + "' '" + bag.string() + "'", &log), 0)
      << log;

  ImportParams p;
  p.ticks_per_revolution = 1 << 16;
  p.nominal_geometry = DiffDriveParams{0.1, 0.1, 0.5};  // a bag from elsewhere does not carry it
  const ImportResult r = importMcap(bag, p);
  const Dataset& d = r.dataset;
  ASSERT_EQ(d.scans.size(), 3u);
  EXPECT_EQ(d.info.config["scan_topic"], "/front/scan");
  const LaserScan& s = d.scans[2].scan;
  EXPECT_NEAR(s.stamp_s, 10.2, 1e-9);
  EXPECT_EQ(s.angle_min_rad, -1.0);
  EXPECT_EQ(s.angle_increment_rad, 0.5);
  EXPECT_EQ(s.time_increment_s, double(0.0225f));
  EXPECT_EQ(s.range_max_m, 12.0);
  EXPECT_EQ(s.ranges_m[2], 5.0);
  EXPECT_EQ(s.ranges_m[3], 0.0625);
  ASSERT_EQ(d.encoders.size(), 13u);
  // Joint angles from names, not positions: left = 1 rad/s, right = 2 rad/s. Ticks of 2^16 per
  // revolution round by at most half a tick.
  const double rad_per_tick = radiansPerTick(p.ticks_per_revolution);
  EXPECT_NEAR(d.encoders[12].ticks_left * rad_per_tick, 0.6, rad_per_tick / 2);
  EXPECT_NEAR(d.encoders[12].ticks_right * rad_per_tick, 1.2, rad_per_tick / 2);
  // The odometry starts where the logged one is at the first joint sample.
  EXPECT_NEAR(d.odom_nominal[0].value.x, 9.9, 1e-9);
  const fs::path dir = scratch / "mcap_ds";
  writeDataset(dir, d);
  EXPECT_EQ(readDataset(dir).scans.size(), 3u);
}

TEST(ImportMcap, ExportedBagRoundTrips) {
  const Dataset d = test::makeSyntheticDataset();
  ExportInput in;
  in.dataset = d;
  const std::string bag = formatMcap(in, {});
  ImportParams p;
  p.nominal_geometry = d.info.nominal_geometry;
  p.ticks_per_revolution = d.info.ticks_per_revolution;
  const ImportResult r = importMcap(bag, "rt.mcap", p);
  ASSERT_EQ(r.dataset.encoders.size(), d.encoders.size());
  for (std::size_t k = 0; k < d.encoders.size(); ++k) {
    EXPECT_EQ(r.dataset.encoders[k].ticks_left, d.encoders[k].ticks_left);
    EXPECT_EQ(r.dataset.encoders[k].ticks_right, d.encoders[k].ticks_right);
  }
  ASSERT_EQ(r.dataset.scans.size(), d.scans.size());
  EXPECT_EQ(r.dataset.scans[3].scan.ranges_m[10], double(float(d.scans[3].scan.ranges_m[10])));
  EXPECT_NEAR(r.dataset.scans[3].scan.stamp_s, d.scans[3].scan.stamp_s, 1e-9);
  EXPECT_NEAR(r.dataset.info.T_base_lidar.yaw, d.info.T_base_lidar.yaw, 1e-15);
  EXPECT_EQ(r.dataset.info.T_base_lidar.x, d.info.T_base_lidar.x);
  EXPECT_EQ(r.dataset.imu.size(), d.imu.size());
}

TEST(ImportMcap, MalformedBagsAreInputErrorsNamingTheOffset) {
  const Dataset d = test::makeSyntheticDataset();
  ExportInput in;
  in.dataset = d;
  ExportParams ep;
  ep.mcap_chunk_size_bytes = 0;
  const std::string bag = formatMcap(in, ep);
  // Every truncation point fails cleanly (sampled: every 997th byte).
  for (std::size_t n = 0; n < bag.size(); n += 997)
    EXPECT_THROW(importMcap(bag.substr(0, n), "t.mcap"), InputError) << n;
  // A bag without odometry or joints.
  ExportInput scans_only;
  scans_only.dataset.scans = d.scans;
  scans_only.dataset.info = d.info;
  try {
    importMcap(formatMcap(scans_only, ep), "s.mcap");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("needs nav_msgs/msg/Odometry"), std::string::npos)
        << e.what();
  }
  // An empty scan.
  ExportInput empty = in;
  empty.dataset.scans[2].scan.ranges_m.clear();
  try {
    importMcap(formatMcap(empty, ep), "e.mcap");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("/scan message 2"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("empty scan"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace slamprep::eval
