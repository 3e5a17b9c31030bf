#include "core/odometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

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

}  // namespace
}  // namespace slamprep
