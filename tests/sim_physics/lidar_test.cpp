#include "slamprep/sim/physics/lidar.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "slamprep/sim/physics/robot.hpp"
#include "slamprep/tests/sim_physics/box_room.hpp"
#include "test_util.hpp"

namespace slamprep::sim {
namespace {

using ::slamprep::test::boxRoomDistance;

TEST(Lidar, HeaderFollowsRosConvention) {
  const Lidar lidar(LidarConfig{}, 1);
  const LaserScan scan = lidar.header(12.5);
  EXPECT_EQ(lidar.beamsPerScan(), 720u);
  EXPECT_EQ(scan.size(), 720u);
  EXPECT_DOUBLE_EQ(scan.stamp_s, 12.5);
  EXPECT_DOUBLE_EQ(scan.angle_min_rad, -std::numbers::pi);
  EXPECT_DOUBLE_EQ(scan.angle_increment_rad, 2 * std::numbers::pi / 720);
  EXPECT_DOUBLE_EQ(scan.time_increment_s, 1.0 / 7200);
  EXPECT_DOUBLE_EQ(scan.scan_time_s, 0.1);
  EXPECT_DOUBLE_EQ(scan.range_min_m, 0.05);
  EXPECT_DOUBLE_EQ(scan.range_max_m, 30.0);
  EXPECT_TRUE(std::isinf(scan.ranges_m[0]) && scan.ranges_m[0] > 0);
  // The last beam ends one increment short of a full turn: 720 beams take 0.1 s - dt.
  EXPECT_NEAR(scan.endTime() - scan.stamp_s, 0.1 - 1.0 / 7200, 1e-15);

  LidarConfig half;
  half.fov_rad = std::numbers::pi;
  half.clockwise = true;
  const Lidar cw(half, 1);
  const LaserScan s = cw.header(0.0);
  EXPECT_EQ(cw.beamsPerScan(), 360u);
  EXPECT_DOUBLE_EQ(s.angle_min_rad, std::numbers::pi / 2);
  EXPECT_DOUBLE_EQ(s.angle_increment_rad, -2 * std::numbers::pi / 720);
  EXPECT_DOUBLE_EQ(cw.beamAngle(359), s.beamAngle(359));
}

// The brief: a still robot in box_room, noise off, off-centre mount, non-zero yaw: every one of
// the 720 ranges equals the analytic distance within 1e-6 m.
TEST(Lidar, StillRobotInBoxRoomMatchesAnalyticRanges) {
  Scene scene(loadWorld(test::worldFile("box_room.yaml")));
  Robot robot(scene, RobotConfig{}, SE2(0.4, -0.3, 0.7));
  for (int k = 0; k < 300; ++k) {
    scene.step(0.001);
    robot.update();
  }
  LidarConfig config;
  config.range_noise_m = 0.0;
  config.T_base_lidar = SE2(0.15, -0.04, 0.3);
  Lidar lidar(config, 3);
  const SE2 T_world_lidar = robot.T_world_base() * config.T_base_lidar;
  double worst = 0.0;
  for (std::size_t i = 0; i < lidar.beamsPerScan(); ++i) {
    const Lidar::Beam beam = lidar.measure(scene, T_world_lidar, i);
    const double yaw = T_world_lidar.yaw + lidar.beamAngle(i);
    const double truth =
        boxRoomDistance(T_world_lidar.translation(), {std::cos(yaw), std::sin(yaw)});
    ASSERT_TRUE(std::isfinite(beam.range_m)) << i;
    EXPECT_EQ(beam.range_m, beam.true_range_m);
    worst = std::max(worst, std::abs(beam.range_m - truth));
  }
  EXPECT_LT(worst, 1e-6);
  RecordProperty("worst_error_m", std::to_string(worst));
}

// Noise: N(0, sigma) per beam. Over n = 720 beams the sample mean has standard error
// sigma/sqrt(n) = 3.7e-4 m and the sample sigma sigma/sqrt(2n) = 2.6e-4 m: 5 standard errors.
TEST(Lidar, NoiseIsGaussianSeededAndPerBeam) {
  const Scene scene(loadWorld(test::worldFile("box_room.yaml")));
  LidarConfig config;  // sigma 0.01 m
  const SE2 T_world_lidar(0.3, 0.2, 0.1);
  auto residuals = [&](std::uint64_t seed) {
    Lidar lidar(config, seed);
    std::vector<double> r;
    for (std::size_t i = 0; i < lidar.beamsPerScan(); ++i) {
      const Lidar::Beam beam = lidar.measure(scene, T_world_lidar, i);
      r.push_back(beam.range_m - beam.true_range_m);
    }
    return r;
  };
  const std::vector<double> a = residuals(42);
  double mean = 0.0, var = 0.0;
  for (double x : a) mean += x / a.size();
  for (double x : a) var += (x - mean) * (x - mean) / (a.size() - 1);
  EXPECT_NEAR(mean, 0.0, 5 * 0.01 / std::sqrt(720.0));
  EXPECT_NEAR(std::sqrt(var), 0.01, 5 * 0.01 / std::sqrt(2 * 720.0));
  EXPECT_EQ(residuals(42), a);  // same seed, same bits
  EXPECT_NE(residuals(43), a);
}

// Correlated noise along the scan: AR(1) with rho = 0.9 keeps sigma (20 scans of 720 beams,
// about 760 independent draws: the sample sigma's standard error 2.6 %, 10 % is a 4-sigma bound)
// and gives consecutive beams rho (standard error sqrt((1 - rho^2) / n) = 0.004: 0.02). Each scan
// starts afresh; rho = 0 is the white noise above, bit for bit.
TEST(Lidar, CorrelatedNoiseKeepsSigmaAndCorrelatesNeighbours) {
  const Scene scene(loadWorld(test::worldFile("box_room.yaml")));
  LidarConfig config;  // sigma 0.01 m
  config.range_noise_correlation = 0.9;
  const SE2 T_world_lidar(0.3, 0.2, 0.1);
  Lidar lidar(config, 7);
  double sum_sq = 0.0, sum_lag = 0.0;
  std::size_t n = 0, pairs = 0;
  for (int scan = 0; scan < 20; ++scan) {
    double previous = 0.0;
    for (std::size_t i = 0; i < lidar.beamsPerScan(); ++i) {
      const Lidar::Beam beam = lidar.measure(scene, T_world_lidar, i);
      const double r = beam.range_m - beam.true_range_m;
      sum_sq += r * r, ++n;
      if (i > 0) sum_lag += r * previous, ++pairs;
      previous = r;
    }
  }
  EXPECT_NEAR(std::sqrt(sum_sq / n), 0.01, 0.1 * 0.01);
  EXPECT_NEAR((sum_lag / pairs) / (sum_sq / n), 0.9, 0.02);
  LidarConfig white = config;
  white.range_noise_correlation = 0.0;
  Lidar a(white, 42), b(LidarConfig{}, 42);
  for (std::size_t i = 0; i < a.beamsPerScan(); ++i)
    EXPECT_EQ(a.measure(scene, T_world_lidar, i).range_m,
              b.measure(scene, T_world_lidar, i).range_m);
}

TEST(Lidar, RangeLimitsGiveNoReturn) {
  const Scene scene(loadWorld(test::worldFile("corridor.yaml")));
  LidarConfig config;
  config.range_noise_m = 0.0;
  Lidar lidar(config, 1);
  // Beam 360 looks along the lidar's +x axis, beam 0 along -x (angle_min = -pi).
  ASSERT_NEAR(lidar.beamAngle(360), 0.0, 1e-15);
  const SE2 T_world_lidar(3.0, 1.25, 0.0);
  const Lidar::Beam far = lidar.measure(scene, T_world_lidar, 360);  // end wall 37 m away
  EXPECT_TRUE(std::isinf(far.range_m));
  EXPECT_TRUE(std::isinf(far.true_range_m));
  const Lidar::Beam back = lidar.measure(scene, T_world_lidar, 0);
  EXPECT_NEAR(back.range_m, 3.0, 1e-12);
  // Closer than range_min (0.05 m): the truth is known, the measurement is no return.
  const Lidar::Beam close = lidar.measure(scene, SE2(0.03, 1.25, 0.0), 0);
  EXPECT_NEAR(close.true_range_m, 0.03, 1e-12);
  EXPECT_TRUE(std::isinf(close.range_m));
}

// A range error fixed in the world: seen again from the same pose it is the same, from another
// pose the spot's (not the beam's), and a lidar without it draws its noise bit for bit as before.
// A range error fixed in the lidar's frame: beam i reads its bias long from any pose, the beams
// beyond the list none.
TEST(Lidar, BiasByBeamIsAddedToItsBeamFromAnyPose) {
  const Scene scene(loadWorld(test::worldFile("box_room.yaml")));
  LidarConfig config;
  config.range_noise_m = 0.0;
  config.range_bias_by_beam_m = "0.05,-0.02,0";
  Lidar lidar(config, 7);
  for (const SE2& T_world_lidar : {SE2(0.3, 0.2, 0.1), SE2(-1.0, 0.5, 2.0)}) {
    std::vector<double> error;
    for (std::size_t i = 0; i < 5; ++i) {
      const Lidar::Beam beam = lidar.measure(scene, T_world_lidar, i);
      error.push_back(beam.range_m - beam.true_range_m);
    }
    EXPECT_NEAR(error[0], 0.05, 1e-12);
    EXPECT_NEAR(error[1], -0.02, 1e-12);
    EXPECT_EQ(error[2], 0.0);
    EXPECT_EQ(error[4], 0.0);
  }
  std::string why;
  EXPECT_FALSE(parseRangeBias("0.01,,0.02", &why));
  EXPECT_NE(why.find("'' is not a number"), std::string::npos) << why;
  EXPECT_EQ(parseRangeBias("", nullptr)->size(), 0u);
}

// A range error by range: each return is off by the curve at its true range, whatever the beam.
TEST(Lidar, BiasByRangeFollowsTheCurveAtTheTrueRange) {
  EXPECT_EQ(rangeBiasAt({}, 3.0), 0.0);
  const std::vector<double> curve{-0.01, 0.0, 0.02};
  EXPECT_NEAR(rangeBiasAt(curve, 0.5), -0.005, 1e-15);
  EXPECT_NEAR(rangeBiasAt(curve, 1.25), 0.005, 1e-15);
  EXPECT_EQ(rangeBiasAt(curve, 7.0), 0.02);  // held beyond the last knot
  EXPECT_EQ(rangeBiasAt(curve, -1.0), -0.01);
  const Scene scene(loadWorld(test::worldFile("box_room.yaml")));
  LidarConfig config;
  config.range_noise_m = 0.0;
  config.range_bias_by_range_m = "-0.01,0,0.02";
  Lidar lidar(config, 7);
  std::size_t hits = 0;
  for (std::size_t i = 0; i < lidar.beamsPerScan(); ++i) {
    const Lidar::Beam beam = lidar.measure(scene, SE2(0.3, 0.2, 0.1), i);
    if (std::isinf(beam.range_m)) continue;
    ++hits;
    EXPECT_NEAR(beam.range_m - beam.true_range_m, rangeBiasAt(curve, beam.true_range_m), 1e-12);
  }
  EXPECT_GT(hits, lidar.beamsPerScan() / 2);
}

TEST(Lidar, FixedErrorIsTheSpotsWhereverItIsSeenFrom) {
  const Scene scene(loadWorld(test::worldFile("box_room.yaml")));
  LidarConfig config;
  config.range_noise_m = 0.0;
  config.range_noise_fixed_m = 0.01;
  const SE2 T_world_lidar(0.3, 0.2, 0.1);
  Lidar lidar(config, 7);
  std::vector<double> first, again;
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < lidar.beamsPerScan(); ++i) {
    const Lidar::Beam beam = lidar.measure(scene, T_world_lidar, i);
    first.push_back(beam.range_m - beam.true_range_m);
    sum_sq += first.back() * first.back();
  }
  for (std::size_t i = 0; i < lidar.beamsPerScan(); ++i) {
    const Lidar::Beam beam = lidar.measure(scene, T_world_lidar, i);
    again.push_back(beam.range_m - beam.true_range_m);
  }
  EXPECT_EQ(again, first);  // the next scan from the same pose: the same errors
  // 720 beams over the room's 20 m of wall, 1000 lengths of 2 cm: sigma within 15 %.
  EXPECT_NEAR(std::sqrt(sum_sq / first.size()), 0.01, 0.0015);
  // From 1 m further along x, the beam that hits the spot of beam k sees its error there.
  const Lidar::Beam k = lidar.measure(scene, T_world_lidar, 90);
  const double yaw = T_world_lidar.yaw + lidar.beamAngle(90);
  const Eigen::Vector2d spot =
      T_world_lidar.translation() + k.true_range_m * Eigen::Vector2d(std::cos(yaw), std::sin(yaw));
  const Eigen::Vector2d from(1.3, 0.2);
  const Eigen::Vector2d dir = (spot - from).normalized();
  const Lidar::Beam seen = lidar.measure(scene, from, dir, 0);
  EXPECT_NEAR(seen.range_m - seen.true_range_m, k.range_m - k.true_range_m, 1e-9);
  // Without it, the per-scan noise is drawn as before.
  LidarConfig plain;
  LidarConfig zero = plain;
  zero.range_noise_fixed_length_m = 0.5;  // no texture: its length changes nothing
  Lidar a(plain, 3), b(zero, 3);
  for (std::size_t i = 0; i < 10; ++i)
    EXPECT_EQ(a.measure(scene, T_world_lidar, i).range_m,
              b.measure(scene, T_world_lidar, i).range_m);
}

}  // namespace
}  // namespace slamprep::sim
