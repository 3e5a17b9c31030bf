#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "slamprep/core/odometry.hpp"
#include "slamprep/sim/drive/controller.hpp"
#include "slamprep/sim/drive/rng.hpp"
#include "slamprep/sim/drive/sensors.hpp"

namespace slamprep::sim {
namespace {

TEST(Controller, UsesTheNominalGeometry) {
  const Scenario s = parseScenario(
      "segments:\n  - {type: arc, v_mps: 0.5, w_radps: 0.4, duration_s: 5}\n", "t.yaml");
  const DiffDriveParams nominal{0.102, 0.0985, 0.52};
  const Controller controller(s.profile, nominal);
  const Eigen::Vector2d rates = controller.wheelRates(2.0);  // inside the hold
  // J_nominal maps the targets back to the command exactly.
  const Eigen::Vector2d twist = nominal.twist(rates.x(), rates.y());
  EXPECT_NEAR(twist.x(), 0.5, 1e-12);
  EXPECT_NEAR(twist.y(), 0.4, 1e-12);
}

// Kanayama et al. 1990: v = v_r cos(e_theta) + k_x e_x, w = w_r + v_r (k_y e_y + k_theta
// sin(e_theta)), the error in the robot's frame whatever the robot's heading; driving backwards
// the heading term keeps its sign (|v_r|), the cross-track term turns the other way.
TEST(Controller, TrackingLawCorrectsTheErrorInTheRobotsFrame) {
  const TrackingParams gains{2.0, 16.0, 8.0, 0.0};
  const Eigen::Vector2d reference(0.5, 0.2);
  const SE2 error(0.1, 0.05, 0.1);
  for (const SE2& T_world_base : {SE2(), SE2(1.0, -2.0, 2.5)}) {
    const Eigen::Vector2d twist =
        trackingTwist(T_world_base, T_world_base * error, reference, gains);
    EXPECT_NEAR(twist.x(), 0.5 * std::cos(0.1) + 2.0 * 0.1, 1e-12);
    EXPECT_NEAR(twist.y(), 0.2 + 0.5 * (16.0 * 0.05 + 8.0 * std::sin(0.1)), 1e-12);
    const Eigen::Vector2d back =
        trackingTwist(T_world_base, T_world_base * error, {-0.5, 0.2}, gains);
    EXPECT_NEAR(back.x(), -0.5 * std::cos(0.1) + 2.0 * 0.1, 1e-12);
    EXPECT_NEAR(back.y(), 0.2 - 0.5 * 16.0 * 0.05 + 0.5 * 8.0 * std::sin(0.1), 1e-12);
    // No error: the feed-forward.
    EXPECT_NEAR((trackingTwist(T_world_base, T_world_base, reference, gains) - reference).norm(),
                0.0, 1e-15);
  }
  EXPECT_EQ(capWheelRates({3.0, -6.0}, 4.0), Eigen::Vector2d(2.0, -4.0));  // the ratio stays
  EXPECT_EQ(capWheelRates({3.0, -2.0}, 4.0), Eigen::Vector2d(3.0, -2.0));
}

// Closed loop: the feed-forward where the robot is on its reference, a correction toward it
// elsewhere, capped; open-loop segments ignore the poses.
TEST(Controller, ClosedLoopTrackCorrectsTowardTheReferenceWithinItsCap) {
  const DiffDriveParams nominal{0.1, 0.1, 0.5};
  const Scenario closed = parseScenario(
      "segments:\n  - {type: track, kind: wheel_rates, period_s: 1, closed_loop: true, "
      "k_y_per_m2: 16, values: [[4, 4], [4, 6]]}\n",
      "t.yaml");
  const Controller controller(closed.profile, nominal);
  ASSERT_TRUE(controller.closedLoop());
  const SE2 here(1.0, 1.0, 0.3);
  EXPECT_NEAR((controller.wheelRates(1.5, here, here) - Eigen::Vector2d(4, 5)).norm(), 0.0, 1e-12);
  // The reference 0.1 m to the left: turn left (right wheel faster), at most 6 rad/s (the
  // knots' largest).
  const Eigen::Vector2d left = controller.wheelRates(1.5, here, here * SE2(0.0, 0.1, 0.0));
  const Eigen::Vector2d expected_twist(0.45, 0.2 + 0.45 * 16.0 * 0.1);
  const Eigen::Vector2d uncapped = nominal.wheelRates(expected_twist.x(), expected_twist.y());
  EXPECT_GT(uncapped.y(), 6.0);
  EXPECT_NEAR((left - uncapped * (6.0 / uncapped.y())).norm(), 0.0, 1e-12);
  const Scenario open = parseScenario(
      "segments:\n  - {type: track, kind: wheel_rates, period_s: 1, values: [[4, 4]]}\n", "t.yaml");
  const Controller open_controller(open.profile, nominal);
  EXPECT_FALSE(open_controller.closedLoop());
  EXPECT_EQ(open_controller.wheelRates(0.5, here, here * SE2(0.0, 0.1, 0.0)),
            open_controller.wheelRates(0.5));
}

TEST(Controller, WheelAngleIncrementIsTheExactIntegral) {
  const Scenario s = parseScenario(
      "segments:\n  - {type: straight, distance_m: 1.3, speed_mps: 0.7}\n"
      "  - {type: wheel_rates, left_radps: -3, right_radps: 5, duration_s: 1.1}\n",
      "t.yaml");
  const Controller controller(s.profile, DiffDriveParams{});
  // The midpoint rule is exact on linear pieces; a cell holding a kink of slope jump J errs by
  // at most J h^2 / 8 (J <= 20 rad/s^2 here, h = 1e-4 s: 2.5e-8 rad per kink, 8 kinks).
  const double t0 = 0.37, t1 = s.profile.duration_s() - 0.2;
  const int n = 40000;
  const double h = (t1 - t0) / n;
  Eigen::Vector2d numeric = Eigen::Vector2d::Zero();
  for (int k = 0; k < n; ++k) numeric += h * controller.wheelRates(t0 + (k + 0.5) * h);
  const Eigen::Vector2d exact = controller.wheelAngleIncrement(t0, t1);
  EXPECT_NEAR(exact.x(), numeric.x(), 2e-7);
  EXPECT_NEAR(exact.y(), numeric.y(), 2e-7);
  // Additive over adjacent intervals.
  const Eigen::Vector2d split =
      controller.wheelAngleIncrement(t0, 1.234) + controller.wheelAngleIncrement(1.234, t1);
  EXPECT_NEAR((split - exact).norm(), 0.0, 1e-12);
}

TEST(Sensors, TicksAreTheFloorOfTheAngle) {
  const double tick = radiansPerTick(4096);
  EXPECT_EQ(quantizeTicks(0.0, 4096), 0);
  EXPECT_EQ(quantizeTicks(0.999 * tick, 4096), 0);
  EXPECT_EQ(quantizeTicks(1.001 * tick, 4096), 1);
  EXPECT_EQ(quantizeTicks(-0.001 * tick, 4096), -1);
  EXPECT_EQ(quantizeTicks(2.0 * std::numbers::pi * 10 + 0.5 * tick, 4096), 40960);
}

TEST(Sensors, SampleClockDoesNotDrift) {
  SampleClock clock(100.0);
  for (int k = 0; k < 123456; ++k) clock.advance();
  EXPECT_EQ(clock.next_s(), 1234.56);
}

TEST(Sensors, ImuNoiseHasItsStatedMeanAndSigma) {
  ImuConfig config;
  config.gyro_bias_radps = 0.01;
  config.gyro_noise_radps = 0.05;
  Imu imu(config, streamSeed(3, RngStream::imu));
  const int n = 20000;
  double sum = 0.0, sum2 = 0.0;
  for (int k = 0; k < n; ++k) {
    const double g = imu.sample(k * 0.005, 0.3, {0, 0}).gyro_z_radps - 0.3;
    sum += g;
    sum2 += g * g;
  }
  const double mean = sum / n;
  const double sigma = std::sqrt(sum2 / n - mean * mean);
  // Standard error of the mean: 0.05 / sqrt(20000) = 3.5e-4; of sigma: 0.05 / sqrt(40000) = 2.5e-4.
  EXPECT_NEAR(mean, 0.01, 4 * 3.5e-4);
  EXPECT_NEAR(sigma, 0.05, 4 * 2.5e-4);
}

// A wheel turning at a constant rate w for T: the counted angle is off by int w s dt, whose
// variance for an Ornstein-Uhlenbeck s started at 0 is
// 2 sigma^2 tau w^2 (T - 2 tau (1 - e^(-T/tau)) + (tau / 2)(1 - e^(-2T/tau))).
double slipVariance(double sigma, double tau, double w, double T) {
  return 2.0 * sigma * sigma * tau * w * w *
         (T - 2.0 * tau * (1.0 - std::exp(-T / tau)) +
          0.5 * tau * (1.0 - std::exp(-2.0 * T / tau)));
}

TEST(Sensors, WheelSlipHasTheVarianceOfAnOrnsteinUhlenbeckProcess) {
  const double sigma = 0.05, tau = 0.5, w = 10.0, dt = 0.01, T = 10.0;
  const int runs = 2000, steps = static_cast<int>(T / dt);
  double sum = 0.0, sum2 = 0.0;
  for (int run = 0; run < runs; ++run) {
    WheelSlip slip(sigma, tau, streamSeed(run, RngStream::encoder_slip));
    Eigen::Vector2d counted = Eigen::Vector2d::Zero();
    for (int k = 0; k < steps; ++k) counted = slip.count(Eigen::Vector2d(w * dt, 0.0), dt);
    const double error = counted.x() - w * T;
    sum += error;
    sum2 += error * error;
  }
  const double expected = slipVariance(sigma, tau, w, T);
  // Standard error of a variance from 2000 draws: sqrt(2 / 2000) = 3.2 %; the steps of 10 ms
  // against tau = 0.5 s add about 1 %.
  EXPECT_NEAR(sum2 / runs / expected, 1.0, 0.12);
  EXPECT_NEAR(sum / runs, 0.0, 4.0 * std::sqrt(expected / runs));
  WheelSlip off(0.0, tau, 1);
  EXPECT_FALSE(off.on());
  EXPECT_EQ(off.count({1.0, 2.0}, dt), Eigen::Vector2d(1.0, 2.0));
}

// Slip in turns: turning on the spot at w, the counted turn (dphi_R - dphi_L) / 2 is off by the
// same variance as a slipping wheel's (the formula above, on the turn); driving straight, the
// counted angles are exact.
TEST(Sensors, TurnSlipChangesTheTurnAndNotTheDistance) {
  const double sigma = 0.05, tau = 0.5, w = 10.0, dt = 0.01, T = 10.0;
  const int runs = 2000, steps = static_cast<int>(T / dt);
  double sum2 = 0.0;
  for (int run = 0; run < runs; ++run) {
    WheelSlip slip(0.0, tau, streamSeed(run, RngStream::encoder_slip), sigma);
    Eigen::Vector2d counted = Eigen::Vector2d::Zero();
    for (int k = 0; k < steps; ++k) counted = slip.count(Eigen::Vector2d(-w * dt, w * dt), dt);
    const double turn_error = 0.5 * (counted.y() - counted.x()) - w * T;
    EXPECT_NEAR(counted.x() + counted.y(), 0.0, 1e-9);  // the distance: none, as driven
    sum2 += turn_error * turn_error;
  }
  const double expected = slipVariance(sigma, tau, w, T);
  EXPECT_NEAR(sum2 / runs / expected, 1.0, 0.12);  // as above
  WheelSlip straight(0.0, tau, 1, sigma);
  EXPECT_TRUE(straight.on());
  Eigen::Vector2d counted;
  for (int k = 0; k < steps; ++k) counted = straight.count(Eigen::Vector2d(w * dt, w * dt), dt);
  EXPECT_NEAR(counted.x(), w * T, 1e-9);
  EXPECT_NEAR(counted.y(), w * T, 1e-9);
}

// Common slip: driving straight at w, both wheels' counted angles are off by the same amount,
// with the variance above; turning on the spot, the counted angles are exact.
TEST(Sensors, CommonSlipChangesTheDistanceAndNotTheTurn) {
  const double sigma = 0.05, tau = 0.5, w = 10.0, dt = 0.01, T = 10.0;
  const int runs = 2000, steps = static_cast<int>(T / dt);
  double sum2 = 0.0;
  for (int run = 0; run < runs; ++run) {
    WheelSlip slip(0.0, tau, streamSeed(run, RngStream::encoder_slip), 0.0, sigma);
    Eigen::Vector2d counted = Eigen::Vector2d::Zero();
    for (int k = 0; k < steps; ++k) counted = slip.count(Eigen::Vector2d(w * dt, w * dt), dt);
    EXPECT_NEAR(counted.y() - counted.x(), 0.0, 1e-9);  // the turn: none, as driven
    sum2 += (counted.x() - w * T) * (counted.x() - w * T);
  }
  EXPECT_NEAR(sum2 / runs / slipVariance(sigma, tau, w, T), 1.0, 0.12);  // as above
  WheelSlip spin(0.0, tau, 1, 0.0, sigma);
  EXPECT_TRUE(spin.on());
  Eigen::Vector2d counted;
  for (int k = 0; k < steps; ++k) counted = spin.count(Eigen::Vector2d(-w * dt, w * dt), dt);
  EXPECT_NEAR(counted.x(), -w * T, 1e-9);
  EXPECT_NEAR(counted.y(), w * T, 1e-9);
}

TEST(Sensors, StreamsAreIndependentAndReproducible) {
  EXPECT_NE(streamSeed(1, RngStream::imu), streamSeed(1, RngStream::lidar));
  EXPECT_NE(streamSeed(1, RngStream::imu), streamSeed(2, RngStream::imu));
  SplitMix64 a(streamSeed(9, RngStream::imu)), b(streamSeed(9, RngStream::imu));
  for (int k = 0; k < 100; ++k) EXPECT_EQ(a.gaussian(), b.gaussian());
}

}  // namespace
}  // namespace slamprep::sim
