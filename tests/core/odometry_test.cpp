#include "slamprep/core/odometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "slamprep/core/error.hpp"
#include "slamprep/core/gyro_odometry.hpp"

namespace slamprep {
namespace {

TEST(DiffDrive, WheelRatesInvertTwist) {
  const DiffDriveParams g{0.102, 0.0985, 0.52};
  const Eigen::Vector2d rates = g.wheelRates(0.8, -0.6);
  const Eigen::Vector2d twist = g.twist(rates.x(), rates.y());
  EXPECT_NEAR(twist.x(), 0.8, 1e-12);
  EXPECT_NEAR(twist.y(), -0.6, 1e-12);
}

TEST(Odometry, ConstantRatesTraceTheExactCircle) {
  // Constant wheel rates give a circle of radius v / w; integration by arcs is exact.
  const DiffDriveParams g{0.1, 0.1, 0.5};
  const int ticks = 4096;
  const Eigen::Vector2d rates = g.wheelRates(1.0, 0.5);
  EncoderLog log;
  for (int k = 0; k <= 100; ++k) {
    const double t = 0.01 * k;
    // Ticks chosen exactly (no rounding) by making the rates multiples of the tick angle.
    log.push_back({t, std::llround(rates.x() * t / radiansPerTick(ticks)),
                   std::llround(rates.y() * t / radiansPerTick(ticks))});
  }
  const PoseSeries odom = integrateEncoders(log, g, ticks);
  ASSERT_EQ(odom.size(), log.size());
  const SE2 end = odom[odom.size() - 1].value;
  // Quantisation: one tick of error per wheel at most over the run.
  const double tick_m = g.radius_left_m * radiansPerTick(ticks);
  EXPECT_NEAR(end.x, 2.0 * std::sin(0.5), 2 * tick_m);
  EXPECT_NEAR(end.y, 2.0 * (1 - std::cos(0.5)), 2 * tick_m);
  EXPECT_NEAR(end.yaw, 0.5, 2 * tick_m / g.wheel_base_m);
}

TEST(Odometry, WheelIncrementStraightAndSpin) {
  const DiffDriveParams g{0.1, 0.1, 0.5};
  const SE2 straight = wheelIncrement(g, 1.0, 1.0);
  EXPECT_NEAR(straight.x, 0.1, 1e-15);
  EXPECT_NEAR(straight.y, 0.0, 1e-15);
  const SE2 spin = wheelIncrement(g, -1.0, 1.0);
  EXPECT_NEAR(spin.x, 0.0, 1e-15);
  EXPECT_NEAR(spin.yaw, 0.2 / 0.5, 1e-15);
}

TEST(GyroOdometry, HeadingInsideTheSamplesAndCarriedOnAtTheEdgeRatesOutside) {
  // Rate 0.5 + 0.2 t at 200 Hz from t = 1: the trapezoids are exact for it at the samples.
  ImuLog imu;
  for (int k = 0; k <= 200; ++k) {
    const double t = 1.0 + 0.005 * k;
    imu.push_back({t, 0.5 + 0.2 * t, 0.0, 0.0});
  }
  const auto integral = [](double t) { return 0.5 * t + 0.1 * t * t - 0.6; };  // from t = 1
  const HeadingSeries heading = gyroHeading(imu);
  for (const double t : {1.0, 1.335, 2.0})
    EXPECT_NEAR(gyroHeadingAt(heading, imu, t), integral(t), 1e-12) << t;
  // Between samples: linear, the interval's mean rate.
  EXPECT_NEAR(gyroHeadingAt(heading, imu, 1.0025), 0.5 * integral(1.005), 1e-12);
  EXPECT_NEAR(gyroHeadingAt(heading, imu, 0.9), -0.1 * 0.7, 1e-15);  // before: 0.7 rad/s
  EXPECT_NEAR(gyroHeadingAt(heading, imu, 2.5), integral(2.0) + 0.5 * 0.9, 1e-12);  // after
  EXPECT_THROW(integrateEncodersGyroHeading({{0.0, 0, 0}}, {}, {0.1, 0.1, 0.5}, 4096), InputError);
}

TEST(GyroOdometry, HeadingFromTheGyroTranslationFromTheWheels) {
  // Both wheels turn alike (the wheels see no turn); the gyro turns at 0.4 rad/s.
  const DiffDriveParams g{0.1, 0.1, 0.5};
  const int ticks = 4096;
  ImuLog imu;
  for (int k = 0; k <= 400; ++k) imu.push_back({0.005 * k, 0.4, 0.0, 0.0});
  EncoderLog encoders;
  for (int k = 0; k <= 100; ++k) encoders.push_back({0.01 * k + 0.002, 7 * k, 7 * k});
  const SE2 start(1.0, 2.0, 0.3);
  const PoseSeries odom = integrateEncodersGyroHeading(encoders, imu, g, ticks, start);
  ASSERT_EQ(odom.size(), encoders.size());
  const double step_m = 0.1 * 7 * radiansPerTick(ticks);
  for (std::size_t k = 1; k < odom.size(); ++k) {
    EXPECT_NEAR(odom[k].value.yaw, 0.3 + 0.4 * 0.01 * k, 1e-12);
    const Eigen::Vector3d xi = between(odom[k - 1].value, odom[k].value).log();
    EXPECT_NEAR(xi.x(), step_m, 1e-15);  // the wheels' distance, along an arc
    EXPECT_NEAR(xi.y(), 0.0, 1e-15);
  }
  // Wheel odometry says straight; this one turns: a circle of radius v / w.
  EXPECT_NEAR(integrateEncoders(encoders, g, ticks, start).samples().back().value.yaw, 0.3, 1e-15);
  const double radius = step_m / 0.01 / 0.4;
  const Eigen::Vector2d centre =
      start.translation() + radius * Eigen::Vector2d(-std::sin(0.3), std::cos(0.3));
  EXPECT_NEAR((odom.samples().back().value.translation() - centre).norm(), radius, 1e-12);
}

TEST(Odometry, AnchoredOnTruthStartsOnTheTruePoseAndKeepsItsShape) {
  // Odometry in its own frame from (5, 0, 0) at t = 1; the truth starts elsewhere, turned.
  PoseSeries odom, truth;
  for (int k = 0; k <= 10; ++k) {
    odom.push_back(1.0 + 0.1 * k, SE2(5.0 + 0.1 * k, 0.0, 0.0));
    truth.push_back(0.5 + 0.1 * k, SE2(1.0, 2.0 + 0.1 * k, std::numbers::pi / 2));
  }
  const auto T_world_odom = anchorOnTruth(odom, truth);
  ASSERT_TRUE(T_world_odom.has_value());
  const PoseSeries world = inWorld(odom, *T_world_odom);
  ASSERT_EQ(world.size(), odom.size());
  // At t0 = 1 the truth is at (1, 2.5, pi/2) (interpolated), and so is the anchored odometry.
  EXPECT_NEAR(world[0].value.x, 1.0, 1e-12);
  EXPECT_NEAR(world[0].value.y, 2.5, 1e-12);
  EXPECT_NEAR(world[0].value.yaw, std::numbers::pi / 2, 1e-12);
  // 0.5 m forward in the odometry is 0.5 m along the true heading (+y) in the world.
  EXPECT_NEAR(world[5].value.x, 1.0, 1e-12);
  EXPECT_NEAR(world[5].value.y, 3.0, 1e-12);
  // No anchor where the truth does not cover the odometry's first stamp, or nothing to anchor.
  PoseSeries late;
  late.push_back(2.0, SE2());
  late.push_back(3.0, SE2());
  EXPECT_FALSE(anchorOnTruth(odom, late).has_value());
  EXPECT_FALSE(anchorOnTruth(PoseSeries(), truth).has_value());
}

}  // namespace
}  // namespace slamprep
