#include "slamprep/core/laser_scan.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace slamprep {
namespace {

LaserScan fullCircle(std::size_t beams, bool clockwise) {
  LaserScan scan;
  const double inc = 2 * std::numbers::pi / beams;
  scan.angle_min_rad = clockwise ? std::numbers::pi : -std::numbers::pi;
  scan.angle_increment_rad = clockwise ? -inc : inc;
  scan.time_increment_s = 0.1 / beams;
  scan.scan_time_s = 0.1;
  scan.range_min_m = 0.1;
  scan.range_max_m = 30.0;
  for (std::size_t i = 0; i < beams; ++i) scan.ranges_m.push_back(1.0 + 0.01 * i);
  return scan;
}

TEST(LaserScan, BeamTimesAndValidity) {
  LaserScan scan = fullCircle(8, false);
  scan.stamp_s = 5.0;
  scan.ranges_m[3] = std::numeric_limits<double>::infinity();
  scan.ranges_m[4] = 0.05;  // below range_min
  EXPECT_DOUBLE_EQ(scan.beamTime(4), 5.0 + 4 * 0.1 / 8);
  EXPECT_DOUBLE_EQ(scan.endTime(), 5.0 + 7 * 0.1 / 8);
  EXPECT_FALSE(scan.valid(3));
  EXPECT_FALSE(scan.valid(4));
  EXPECT_EQ(scan.points().size(), 6u);
}

TEST(LaserScan, RepackOfOwnPointsIsIdentity) {
  for (bool clockwise : {false, true}) {
    const LaserScan scan = fullCircle(720, clockwise);
    std::vector<std::optional<Eigen::Vector2d>> p;
    for (std::size_t i = 0; i < scan.size(); ++i) p.push_back(scan.point(i));
    const LaserScan out = repackPoints(scan, p);
    ASSERT_EQ(out.size(), scan.size());
    for (std::size_t i = 0; i < scan.size(); ++i)
      EXPECT_NEAR(out.ranges_m[i], scan.ranges_m[i], 1e-12) << "beam " << i << " cw " << clockwise;
  }
}

TEST(LaserScan, RepackLeavesEmptyBinsWithoutReturn) {
  const LaserScan scan = fullCircle(16, false);
  std::vector<std::optional<Eigen::Vector2d>> p(scan.size());
  p[2] = scan.point(2);
  const LaserScan out = repackPoints(scan, p);
  EXPECT_TRUE(out.valid(2));
  EXPECT_FALSE(out.valid(3));
}

}  // namespace
}  // namespace slamprep
