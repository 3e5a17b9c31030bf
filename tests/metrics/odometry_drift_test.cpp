#include "slamprep/eval/metrics/odometry_drift.hpp"

#include <gtest/gtest.h>

#include <numbers>

namespace slamprep::eval {
namespace {

// Ground truth drives 1 m/s along a line starting at (5, 2) heading 90 deg, 100 Hz for 10 s.
// Odometry in its own frame starts at the origin heading 0 and believes it drives `speed`.
struct Line {
  PoseSeries gt;
  PoseSeries odometry(double speed, double yaw_rate = 0.0) const {
    PoseSeries odom;
    for (const auto& x : gt.samples())
      odom.push_back(x.stamp_s, SE2::exp({speed * x.stamp_s, 0.0, yaw_rate * x.stamp_s}));
    return odom;
  }
  Line() {
    for (int k = 0; k <= 1000; ++k)
      gt.push_back(0.01 * k, SE2(5.0, 2.0 + 0.01 * k, std::numbers::pi / 2));
  }
};

TEST(OdometryDrift, ScaleErrorGrowsLinearly) {
  const Line line;
  const DriftResult r = odometryDrift(line.odometry(1.05), line.gt);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_EQ(r.matched, 1001u);
  // 5 % too far after 10 m: 0.5 m, largest at the end; heading stays exact.
  EXPECT_NEAR(r.final_position_error_m, 0.5, 1e-12);
  EXPECT_NEAR(r.max_position_error_m, 0.5, 1e-12);
  EXPECT_NEAR(r.final_heading_error_deg, 0.0, 1e-12);
  EXPECT_NEAR(r.path_length_m, 10.0, 1e-9);
  EXPECT_NEAR(r.duration_s, 10.0, 1e-12);
  EXPECT_NEAR(r.T_world_odom.x, 5.0, 1e-12);
  EXPECT_NEAR(r.T_world_odom.yaw, std::numbers::pi / 2, 1e-15);
  // The error pose in the true frame: 0.5 m too far ahead along the robot's own x.
  EXPECT_NEAR(r.final_error.x, 0.5, 1e-12);
  EXPECT_NEAR(r.final_error.y, 0.0, 1e-12);
}

TEST(OdometryDrift, FinalErrorKeepsTheHeadingSign) {
  const Line line;
  // Odometry turning left at 0.01 rad/s while the truth drives straight: +0.1 rad after 10 s
  // (odometry minus truth), which the absolute final_heading_error_deg cannot tell from -0.1.
  const DriftResult r = odometryDrift(line.odometry(1.0, 0.01), line.gt);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.final_error.yaw, 0.1, 1e-12);
  EXPECT_NEAR(r.final_heading_error_deg, 0.1 * 180.0 / std::numbers::pi, 1e-9);
  EXPECT_NEAR(r.final_error.translation().norm(), r.final_position_error_m, 1e-15);
  EXPECT_LT(odometryDrift(line.odometry(1.0, -0.01), line.gt).final_error.yaw, -0.0999);
}

TEST(OdometryDrift, HeadingErrorAndMaxBeforeTheEnd) {
  const Line line;
  // Odometry drives a full circle (radius R = 10 / 2 pi) in 10 s at 1 m/s, the truth a straight
  // line. In the start frame |l - c|^2 = (t - R sin wt)^2 + R^2 (1 - cos wt)^2 grows
  // monotonically (t - R sin wt has derivative 1 - cos wt >= 0): the largest error is the
  // final one, 10 m, where the circle is back at the start.
  const double w = 2 * std::numbers::pi / 10.0;
  const DriftResult r = odometryDrift(line.odometry(1.0, w), line.gt);
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.final_position_error_m, 10.0, 1e-9);
  EXPECT_NEAR(r.max_position_error_m, 10.0, 1e-9);
  EXPECT_NEAR(r.final_heading_error_deg, 0.0, 1e-9);  // a full turn wraps to 0
  // Halfway the heading error is 180 deg.
  PoseSeries half;
  const PoseSeries circle = line.odometry(1.0, w);
  for (const auto& x : circle.samples())
    if (x.stamp_s <= 5.0 + 1e-9) half.push_back(x.stamp_s, x.value);
  EXPECT_NEAR(odometryDrift(half, line.gt).final_heading_error_deg, 180.0, 1e-6);
}

TEST(OdometryDrift, ComparesNominalWithCalibrated) {
  const Line line;
  const DriftComparison c = compareDrift(line.odometry(1.05), line.odometry(1.01), line.gt);
  ASSERT_TRUE(c.ok) << c.reason;
  EXPECT_NEAR(*c.final_position_ratio, 5.0, 1e-9);  // 0.5 m vs 0.1 m
  EXPECT_NEAR(*c.max_position_ratio, 5.0, 1e-9);
  EXPECT_FALSE(c.final_heading_ratio.has_value());  // both 0: no ratio rather than NaN
  const DriftComparison exact = compareDrift(line.odometry(1.05), line.gt, line.gt);
  EXPECT_FALSE(exact.final_position_ratio.has_value());
}

TEST(OdometryDrift, RefusesWithoutOverlap) {
  const Line line;
  PoseSeries late;
  late.push_back(100.0, SE2());
  EXPECT_FALSE(odometryDrift(late, line.gt).ok);
  EXPECT_FALSE(compareDrift(late, line.gt, line.gt).ok);
}

}  // namespace
}  // namespace slamprep::eval
