// CARMEN import on the committed excerpts of the SLAM benchmark logs (tests/data/carmen_*, each
// with a README of what it holds) and the stamp-order rules on small hand-written logs.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/carmen.hpp"
#include "slamprep/eval/formats/import.hpp"
#include "slamprep/eval/formats/text_io.hpp"

namespace slamprep::eval {
namespace {

constexpr double kDegree = std::numbers::pi / 180;

std::string excerpt(const std::string& name) {
  return std::string(SLAMPREP_SOURCE_DIR) + "/tests/data/" + name;
}

ImportResult importExcerpt(const std::string& name, const ImportParams& p = {}) {
  const std::string file = excerpt(name);
  return importCarmen(readTextFile(file), file, p);
}

std::string refusal(const std::string& text, const ImportParams& p = {}) {
  try {
    importCarmen(text, "x.clf", p);
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(CarmenExcerpts, AcesImportsWithItsOdomLinesAndZeroMount) {
  const ImportResult r = importExcerpt("carmen_aces/aces_first120s.clf");
  const Dataset& d = r.dataset;
  // README: 741 ODOM, 740 FLASER lines, 180 beams, stamps increasing within each type.
  EXPECT_EQ(d.scans.size(), 740u);
  EXPECT_EQ(d.odom_nominal.size(), 741u);
  EXPECT_EQ(d.scans[0].scan.size(), 180u);
  EXPECT_NEAR(d.scans[0].scan.angle_increment_rad, kDegree, 1e-15);
  EXPECT_EQ(d.scans[0].scan.angle_min_rad, -std::numbers::pi / 2);
  EXPECT_EQ(r.summary.odometry, "741 ODOM lines");
  EXPECT_TRUE(contains(r.summary.lidar_mount, "from PARAM robot_frontlaser_offset"));
  EXPECT_TRUE(r.summary.reordered.empty());
  EXPECT_TRUE(r.summary.dropped.empty());
  // laser pose == odometry on every line; the one note is the no-return value: ACES's SICK
  // writes 50.00 m for no return (987 of 133 200 readings, none within a metre below).
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_TRUE(contains(r.notes[0], "987 readings (0.741 %) at 50 m")) << r.notes[0];
  ASSERT_TRUE(r.summary.range && r.summary.range->no_return_applied);
  EXPECT_EQ(d.info.config.at("no_return_value_m"), 50.0);
  std::size_t no_return = 0;
  for (const auto& s : d.scans) {
    EXPECT_EQ(s.scan.range_max_m, 50.0);
    for (double range : s.scan.ranges_m) no_return += std::isinf(range);
  }
  EXPECT_EQ(no_return, 987u);
  // No per-beam timing in CARMEN: said, not invented.
  EXPECT_EQ(d.scans[0].scan.time_increment_s, 0.0);
  EXPECT_TRUE(contains(r.summary.time_increment, "no per-beam timing"));
  EXPECT_TRUE(d.encoders.empty());
}

TEST(CarmenExcerpts, Fr079MountIsTheFrontLaserOffsetParam) {
  // The first FLASER (1211.520329) precedes the first ODOM (1211.530144): dropped unless
  // --no-trim, which refuses it.
  ImportParams strict;
  strict.trim = false;
  EXPECT_TRUE(contains(refusal(readTextFile(excerpt("carmen_fr079/fr079_first60s.clf")), strict),
                       "scan at 1211.520329"));
  const ImportResult r = importExcerpt("carmen_fr079/fr079_first60s.clf", {});
  const Dataset& d = r.dataset;
  EXPECT_EQ(d.info.T_base_lidar.x, -0.04);
  EXPECT_EQ(d.info.T_base_lidar.y, 0.0);
  EXPECT_EQ(d.info.T_base_lidar.yaw, 0.0);
  EXPECT_EQ(r.summary.lidar_mount,
            "x -0.04 m, y 0 m, yaw 0 deg from PARAM robot_frontlaser_offset");
  // The FLASER laser poses sit 0.04 m behind the robot poses: they agree with the PARAM, so no
  // note (rounding of the logged 6 decimals stays below 1e-3).
  EXPECT_TRUE(r.notes.size() == 1 && contains(r.notes[0], "--trim")) << r.notes.size();
  EXPECT_EQ(d.scans.size(), 277u);
  EXPECT_EQ(r.summary.dropped.at("scans outside the odometry (--trim)"), 1u);
  EXPECT_EQ(d.scans[0].scan.size(), 360u);
  EXPECT_NEAR(d.scans[0].scan.angle_increment_rad, kDegree / 2, 1e-15);
}

TEST(CarmenExcerpts, MitCsailFlaserOnlyTakesTheOdometryFromTheLaserLines) {
  const ImportResult r = importExcerpt("carmen_mit_csail/mit-csail_first60s.clf");
  const Dataset& d = r.dataset;
  ASSERT_EQ(d.scans.size(), 282u);
  ASSERT_EQ(d.odom_nominal.size(), 282u);
  // Line 4: ... 576.536523 0.106594 -2.255213 (odom_x odom_y odom_theta) 1134864629.895182.
  EXPECT_EQ(d.odom_nominal[0].stamp_s, 1134864629.895182);
  EXPECT_EQ(d.odom_nominal[0].value.x, 576.536523);
  EXPECT_EQ(d.odom_nominal[0].value.yaw, -2.255213);
  EXPECT_EQ(r.summary.odometry,
            "282 FLASER lines' robot poses (odom_x odom_y odom_theta): the log has no ODOM lines");
  EXPECT_EQ(d.info.config["odometry_from"], r.summary.odometry);
  EXPECT_EQ(d.scans[0].scan.size(), 361u);
  EXPECT_NEAR(d.scans[0].scan.beamAngle(360), std::numbers::pi / 2, 1e-12);
  // Its laser poses are its robot poses on every line: the mount is identity, and says why.
  EXPECT_EQ(d.info.T_base_lidar.x, 0.0);
  EXPECT_TRUE(contains(r.summary.lidar_mount, "the same on every FLASER line"))
      << r.summary.lidar_mount;
}

TEST(CarmenExcerpts, FrClinicRobotLaserCarriesItsOwnAnglesAndPoses) {
  const ImportResult r = importExcerpt("carmen_fr_clinic/fr-clinic_robotlaser_first200lines.clf");
  const Dataset& d = r.dataset;
  ASSERT_EQ(d.scans.size(), 200u);
  EXPECT_EQ(d.odom_nominal.size(), 200u);
  EXPECT_EQ(r.summary.scans,
            "200 ROBOTLASER1 lines, 180..181 beams; angles and max range from each line");
  EXPECT_EQ(d.scans[0].scan.angle_min_rad, -1.570796);
  // The lines say 81.9 m; 81.83 m is the SICK's code for no return (90 readings here).
  EXPECT_EQ(d.scans[0].scan.range_max_m, 81.83);
  // No PARAM, but every line's laser pose is 0.22 m ahead of its robot pose: the configured
  // offset, adopted (before, identity: the matched "base" was the laser's path).
  EXPECT_NEAR(d.info.T_base_lidar.x, 0.22, 1e-6);
  EXPECT_NEAR(d.info.T_base_lidar.y, 0.0, 1e-6);
  EXPECT_TRUE(contains(r.summary.lidar_mount, "the same on every ROBOTLASER1 line"));
  ASSERT_EQ(r.notes.size(), 1u);
  EXPECT_TRUE(contains(r.notes[0], "90 readings")) << r.notes[0];
}

TEST(CarmenExcerpts, IntelStampsRunBackBeyondTheDefaultTolerance) {
  // ODOM line 26 is stamped 976052858.40413, line 28 falls back to 976052858.139632.
  const std::string text = readTextFile(excerpt("carmen_intel/intel_first180s.clf"));
  const std::string why = refusal(text);
  EXPECT_TRUE(contains(why,
                       "x.clf:28: timestamp: 976052858.139632 is 0.264498 s before "
                       "976052858.40413 on line 26 (ODOM)"))
      << why;
  // Within 1 s every backward step is covered: sorted, or the late lines dropped. Counts from
  // the excerpt by an independent script (lines not at their sorted position; lines stamped at
  // or after a later line of their type); the last FLASER lies after the last ODOM (--trim).
  ImportParams p;
  p.reorder_tolerance_s = 1.0;
  p.trim = true;
  const ImportResult sorted = importCarmen(text, "x.clf", p);
  EXPECT_EQ(sorted.summary.reordered.at("ODOM"), 366u);
  EXPECT_EQ(sorted.summary.reordered.at("FLASER"), 169u);
  EXPECT_EQ(sorted.dataset.scans.size(), 911u);
  p.drop_late_stamps = true;
  const ImportResult dropped = importCarmen(text, "x.clf", p);
  EXPECT_TRUE(dropped.summary.reordered.empty());
  EXPECT_EQ(dropped.summary.dropped.at("ODOM: stamped at or after a later ODOM line "
                                       "(--out-of-order drop)"),
            119u);
  EXPECT_EQ(dropped.summary.dropped.at("FLASER: stamped at or after a later FLASER line "
                                       "(--out-of-order drop)"),
            55u);
  EXPECT_EQ(dropped.dataset.odom_nominal.size(), 1797u - 119u);
}

TEST(CarmenOrder, StampsSlightlyOutOfOrderAreSortedAndCounted) {
  // ODOM 10.08 arrives after 10.10 (0.02 s late), FLASER 10.15 after 10.17 (0.02 s).
  const std::string log =
      "ODOM 0 0 0 0 0 0 10.00 h 0\n"
      "ODOM 0.1 0 0 0 0 0 10.10 h 0\n"
      "ODOM 0.08 0 0 0 0 0 10.08 h 0\n"
      "FLASER 2 1 1 0.2 0 0 0.2 0 0 10.17 h 0\n"
      "FLASER 2 1 1 0.15 0 0 0.15 0 0 10.15 h 0\n"
      "ODOM 0.3 0 0 0 0 0 10.30 h 0\n"
      "SYNC tag\n";
  const ImportResult r = importCarmen(log, "x.clf");
  EXPECT_EQ(r.summary.reordered.at("ODOM"), 2u);  // 10.10 and 10.08 swap places
  EXPECT_EQ(r.summary.reordered.at("FLASER"), 2u);
  EXPECT_EQ(r.summary.dropped.at("SYNC: not read"), 1u);
  const PoseSeries& odom = r.dataset.odom_nominal;
  ASSERT_EQ(odom.size(), 4u);
  EXPECT_EQ(odom[1].stamp_s, 10.08);
  EXPECT_EQ(odom[1].value.x, 0.08);  // the pose stays with its stamp
  EXPECT_EQ(r.dataset.scans[0].scan.stamp_s, 10.15);
  // With a tolerance of 0.01 s the same log is refused, naming both lines and stamps.
  ImportParams p;
  p.reorder_tolerance_s = 0.01;
  EXPECT_TRUE(contains(refusal(log, p),
                       "x.clf:3: timestamp: 10.08 is 0.020000 s before 10.1 on "
                       "line 2 (ODOM): out of order by more than the reorder "
                       "tolerance 0.010000 s"))
      << refusal(log, p);
  // A message logged twice (the full ACES log has ODOM line 14032 = line 14030) is dropped.
  const ImportResult twice = importCarmen(
      "ODOM 0 0 0 0 0 0 1.0 h 0\nFLASER 2 1 1 0 0 0 0 0 0 1.01 h 0\nODOM 0 0 0 0 0 0 1.0 h 0\n"
      "ODOM 1 0 0 0 0 0 1.1 h 0\n",
      "x.clf");
  EXPECT_EQ(twice.dataset.odom_nominal.size(), 2u);
  EXPECT_EQ(twice.summary.dropped.at("ODOM: identical to the previous ODOM line"), 1u);
  // Equal stamps cannot be ordered, even when they arrive apart.
  EXPECT_TRUE(contains(refusal("ODOM 0 0 0 0 0 0 1.0 h 0\nODOM 0 0 0 0 0 0 1.02 h 0\n"
                               "ODOM 0 0 0 0 0 0 1.0 h 0\nFLASER 2 1 1 0 0 0 0 0 0 1.01 h 0\n"),
                       "x.clf:3: timestamp: duplicate timestamp 1 (also on line 1)"));
}

TEST(CarmenOrder, OtherLaserMessagesAndTheirMounts) {
  const std::string log =
      "PARAM robot_frontlaser_offset 0.3 h 0\n"
      "PARAM robot_rearlaser_offset -0.25 h 0\n"
      "ODOM 0 0 0 0 0 0 1.0 h 0\n"
      "ODOM 1 0 0 0 0 0 2.0 h 0\n"
      "RLASER 3 1 2 3 0.5 0 0 0.5 0 0 1.5 h 0\n"
      "RAWLASER1 0 -1 2 1 10 0.01 0 3 1 2 3 0 1.6 h 0\n"
      "FLASER 3 1 2 3 0.8 0 0 0.5 0 0 1.7 h 0\n";
  const ImportResult front = importCarmen(log, "x.clf");  // FLASER comes before RLASER
  EXPECT_EQ(front.dataset.info.T_base_lidar.x, 0.3);
  EXPECT_EQ(front.summary.dropped.at("RLASER: another laser (--laser RLASER imports it)"), 1u);
  ImportParams p;
  p.laser = "RLASER";
  const ImportResult rear = importCarmen(log, "x.clf", p);
  EXPECT_EQ(rear.dataset.info.T_base_lidar.x, -0.25);
  EXPECT_EQ(rear.dataset.info.T_base_lidar.yaw, std::numbers::pi);  // looks backwards
  p.laser = "RAWLASER1";
  const ImportResult raw = importCarmen(log, "x.clf", p);
  ASSERT_EQ(raw.dataset.scans.size(), 1u);
  EXPECT_EQ(raw.dataset.scans[0].scan.angle_min_rad, -1.0);
  EXPECT_EQ(raw.dataset.scans[0].scan.range_max_m, 10.0);
  EXPECT_EQ(raw.dataset.info.T_base_lidar.x, 0.0);  // no mount PARAM for raw lasers
  p.odometry = "laser";
  EXPECT_TRUE(contains(refusal(log, p), "RAWLASER1 lines carry no pose"));
  p.laser = "ROBOTLASER1";
  EXPECT_TRUE(contains(refusal(log, p), "no ROBOTLASER1 lines"));
}

}  // namespace
}  // namespace slamprep::eval
