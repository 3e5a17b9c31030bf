#include "slamprep/algo/deskew/beam_transform.hpp"

#include <gtest/gtest.h>

#include <numbers>

#include "slamprep/core/laser_scan.hpp"

namespace slamprep::algo {
namespace {

LaserScan ringScan(std::size_t beams, double angle_increment_rad) {
  LaserScan s;
  s.stamp_s = 5.0;
  s.angle_min_rad = -2.0;
  s.angle_increment_rad = angle_increment_rad;
  s.time_increment_s = 1e-4;
  s.range_min_m = 0.1;
  s.range_max_m = 20.0;
  for (std::size_t i = 0; i < beams; ++i) s.ranges_m.push_back(1.0 + 0.01 * (i % 37));
  s.ranges_m[3] = std::numeric_limits<double>::infinity();  // no return
  s.ranges_m[4] = 0.05;                                     // below range_min
  return s;
}

// The incremental kernel against the direct formula T(t_i) * p_i with trigonometry per beam:
// 2000 beams across three knots; the recurrences re-anchor every 64 beams, so the drift is ~64
// roundings (~1e-14 m), far inside 1e-12.
TEST(TransformBeams, MatchesDirectEvaluation) {
  for (double inc : {2 * std::numbers::pi / 2000, -2 * std::numbers::pi / 2000}) {
    const LaserScan scan = ringScan(2000, inc);
    PoseSeries knots;
    knots.push_back(5.0 - 0.01, SE2(0.1, -0.2, 0.3));
    knots.push_back(5.08, SE2(0.3, 0.1, 0.5));
    knots.push_back(5.25, SE2(0.2, 0.4, -0.1));
    std::vector<std::optional<Eigen::Vector2d>> out;
    transformBeams(scan, scan.stamp_s, toTrajectory(knots), out);
    ASSERT_EQ(out.size(), scan.size());
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (!scan.valid(i)) {
        EXPECT_FALSE(out[i]) << i;
        continue;
      }
      ASSERT_TRUE(out[i]) << i;
      const Eigen::Vector2d expected = *knots.at(scan.beamTime(i)) * scan.point(i);
      EXPECT_LT((*out[i] - expected).norm(), 1e-12) << i;
    }
  }
}

TEST(TransformBeams, OneKnotIsOnePose) {
  const LaserScan scan = ringScan(100, 0.01);
  PoseSeries knots;
  knots.push_back(0.0, SE2(1.0, 2.0, 0.5));
  std::vector<std::optional<Eigen::Vector2d>> out;
  transformBeams(scan, scan.stamp_s, toTrajectory(knots), out);
  EXPECT_LT((*out[10] - SE2(1.0, 2.0, 0.5) * scan.point(10)).norm(), 1e-14);
}

}  // namespace
}  // namespace slamprep::algo
