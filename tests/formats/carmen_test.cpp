// CARMEN log reader: a hand-written log, and every malformed case named with file, line, field.
#include "slamprep/eval/formats/carmen.hpp"

#include <gtest/gtest.h>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/export.hpp"
#include "synthetic_dataset.hpp"

namespace slamprep::eval {
namespace {

// Written by hand from the CARMEN field order (docs/export.md): 5 beams of pi/4 from -pi/2.
const char* kLog =
    "# a comment\n"
    "PARAM robot_front_laser_max 80\n"
    "ODOM 0 0 0 0 0 0 100.0 host 100.0\n"
    "ODOM 0.1 0 0 0.5 0 0 100.2 host 100.2\n"
    "ROBOTLASER1 0 -1.5707963267948966 3.141592653589793 0.7853981633974483 20 0.01 0 5 "
    "1.0 2.0 20 3.0 4.5 0 0.2 0 0 0.05 0 0 0.5 0 0 0 0 100.1 host 100.1\n"
    "ODOM 0.2 0.01 0.1 0.5 0 0 100.4 host 100.4\n"
    "ROBOTLASER1 0 -1.5707963267948966 3.141592653589793 0.7853981633974483 20 0.01 0 5 "
    "1.5 2.5 3.5 20 5.5 2 7 8 0.3 0 0 0.15 0 0 0.5 0 0 0 0 100.3 host 100.3\n";

TEST(Carmen, ReadsAHandWrittenLog) {
  const CarmenLog log = parseCarmen(kLog, "run.clf");
  ASSERT_EQ(log.odometry.size(), 3u);
  ASSERT_EQ(log.lasers.size(), 1u);
  ASSERT_EQ(log.lasers.at(CarmenLaserType::kRobotLaser1).size(), 2u);
  EXPECT_TRUE(log.skipped.empty());
  EXPECT_EQ(log.comment_lines, 1u);
  EXPECT_EQ(log.params.at("robot_front_laser_max").value, "80");
  EXPECT_EQ(log.params.at("robot_front_laser_max").line, 2u);
  EXPECT_EQ(log.odometry[2].T_odom_base.yaw, 0.1);
  EXPECT_EQ(log.odometry[2].stamp_s, 100.4);
  const CarmenLaser& l = log.lasers.at(CarmenLaserType::kRobotLaser1)[1];
  EXPECT_EQ(l.line, 7u);
  EXPECT_EQ(l.scan.stamp_s, 100.3);
  EXPECT_EQ(l.scan.angle_min_rad, -1.5707963267948966);
  EXPECT_EQ(l.scan.angle_increment_rad, 0.7853981633974483);
  EXPECT_EQ(l.scan.range_max_m, 20.0);
  ASSERT_EQ(l.scan.size(), 5u);
  EXPECT_EQ(l.scan.ranges_m[0], 1.5);
  EXPECT_TRUE(std::isinf(l.scan.ranges_m[3])) << "a max-range reading is no return";
  EXPECT_EQ(l.T_odom_laser->x, 0.3);
  EXPECT_EQ(l.T_odom_base->x, 0.15);
}

TEST(Carmen, ReadsFlaserWithCarmensAngleGuess) {
  std::string line = "FLASER 181";
  for (int i = 0; i < 181; ++i) line += " 1.5";
  line += " 1 2 0.5 1 2 0.5 7.25 host 7.25\n";
  const CarmenLog log = parseCarmen(line, "old.log");
  ASSERT_EQ(log.lasers.at(CarmenLaserType::kFlaser).size(), 1u);
  const CarmenLaser& l = log.lasers.at(CarmenLaserType::kFlaser)[0];
  EXPECT_NEAR(l.scan.angle_increment_rad, M_PI / 180, 1e-15);
  EXPECT_EQ(l.scan.beamAngle(180), -M_PI / 2 + 180 * (M_PI / 180));
  EXPECT_EQ(l.scan.stamp_s, 7.25);
}

TEST(Carmen, ReadsWhatTheExporterWrites) {
  const Dataset d = test::makeSyntheticDataset();
  const CarmenLog log = parseCarmen(formatCarmen(d, d.scans, {}), "x.clf");
  const auto& lasers = log.lasers.at(CarmenLaserType::kRobotLaser1);
  ASSERT_EQ(lasers.size(), d.scans.size());
  ASSERT_EQ(log.odometry.size(), d.odom_nominal.size());
  for (std::size_t i = 0; i < d.scans.size(); ++i) {
    const LaserScan& a = d.scans[i].scan;
    const LaserScan& b = lasers[i].scan;
    EXPECT_EQ(b.stamp_s, a.stamp_s);
    for (std::size_t k = 0; k < a.size(); ++k) ASSERT_EQ(b.ranges_m[k], a.ranges_m[k]);
  }
}

struct BadCase {
  std::string text;
  std::string expected;  // substring of the error after "bad.clf:<line>: "
};

TEST(Carmen, MalformedLinesNameFileLineAndField) {
  const std::string rl = "ROBOTLASER1 0 -1.5707963267948966 3.141592653589793 0.7853981633974483 ";
  const std::string tail = " 0 0.2 0 0 0.05 0 0 0.5 0 0 0 0 100.1 host 100.1\n";
  const std::vector<BadCase> cases = {
      {rl + "20 0.01 0 5 1 2", "num_readings: 5 values announced"},
      {rl + "20 0.01 0 5 1 2 nan 3 4" + tail, "range_readings"},
      {rl + "20 0.01 0 5 1 2 inf 3 4" + tail, "range_readings"},
      {rl + "20 0.01 0 5 1 2 -3 3 4" + tail, "range_readings: beam 2 is negative"},
      {rl + "20 0.01 0 1000000000 1 2 3 4 5" + tail, "num_readings: 1000000000 values announced"},
      {rl + "20 0.01 0 0" + tail, "num_readings: empty scan"},
      {rl + "20 0.01 0 -5 1 2 3 4 5" + tail, "num_readings: negative"},
      {rl + "-20 0.01 0 5 1 2 3 4 5" + tail, "maximum_range: must be > 0"},
      {"ROBOTLASER1 0 -1.57 1.0 0.7853981633974483 20 0.01 0 5 1 2 3 4 5" + tail, "field_of_view"},
      {"ROBOTLASER1 0 -1.57 3.14 0 20 0.01 0 5 1 2 3 4 5" + tail, "angular_resolution"},
      {rl + "20 0.01 0 5 1 2 3 4 5 0 0.2 0 0 0.05 0 0 0.5 0 0 0 0 100.1 host 100.1 extra more",
       "trailing fields"},
      {rl + "20 0.01 0 5 1 2 3x 4 5" + tail, "range_readings"},
      {"ODOM 0 0 0 0 0\n", "accel: missing (line has only 6 fields)"},
      {"ODOM 0 nan 0 0 0 0 5 h 5\n", "y"},
      // Same stamp, other pose (an identical line is a repeat, dropped: CarmenOrder tests).
      {"ODOM 0 0 0 0 0 0 5 h 5\nODOM 0.1 0 0 0 0 0 5 h 5\n", "timestamp: duplicate"},
      {"ODOM 0 0 0 0 0 0 5 h 5\nODOM 0 0 0 0 0 0 4 h 4\n", "timestamp"},
      {"FLASER 1 5 0 0 0 0 0 0 1 h 1\n", "need at least 2 beams"},
  };
  for (const BadCase& c : cases) {
    try {
      parseCarmen(c.text, "bad.clf");
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.rfind("bad.clf:", 0), 0u) << what;
      EXPECT_NE(what.find(c.expected), std::string::npos)
          << "expected \"" << c.expected << "\" in: " << what;
    }
  }
}

TEST(Carmen, EveryPrefixOfALogIsReadOrRefusedCleanly) {
  const std::string text = kLog;
  for (std::size_t n = 0; n <= text.size(); ++n) {
    try {
      parseCarmen(text.substr(0, n), "t.clf");
    } catch (const InputError&) {
    }
  }
}

}  // namespace
}  // namespace slamprep::eval
