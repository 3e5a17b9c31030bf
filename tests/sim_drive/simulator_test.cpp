#include "slamprep/sim/drive/simulator.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/sim/drive/controller.hpp"
#include "slamprep/tests/sim_drive/square_room.hpp"
#include "slamprep/tests/support/cli_run.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::sim {
namespace {

using slamprep::test::slurp;

using test::scenario;
using test::squareRoom;

SimConfig config(SimMode mode, int beams = 90) {
  SimConfig c;
  c.mode = mode;
  c.lidar.beams_per_revolution = beams;  // keeps the tests fast where beams don't matter
  return c;
}

double tickAngle(const SimConfig& c) {
  return radiansPerTick(c.encoders.ticks_per_revolution);
}

// ---- Distortion --------------------------------------------------------------------------------

/// With a constant body twist xi = (v_x, v_y, w) of the base, the lidar frame at beam i is the
/// stamp's lidar frame moved by T_BL^-1 exp(xi dt) T_BL, dt = t_i - t_stamp, so the undistorted
/// point is p_ref = T_BL^-1 exp(xi dt) T_BL p_L. Returns the worst deviation from that
/// prediction and the largest distortion |p_ref - p_L| seen, over scans inside [t_from, t_to].
struct SpinCheck {
  double worst_prediction_error_m = 0.0;
  double largest_distortion_m = 0.0;
  std::size_t beams = 0;
};
SpinCheck checkSpin(const Dataset& data, const SE2& T_base_lidar, const Eigen::Vector3d& xi,
                    double t_from, double t_to) {
  SpinCheck check;
  for (const ScanRecord& record : data.scans) {
    const LaserScan& scan = record.scan;
    if (scan.stamp_s < t_from || scan.endTime() > t_to) continue;
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (!record.p_ref_true[i]) continue;
      const Eigen::Vector2d p_lidar = scan.point(i);
      const double dt = scan.beamTime(i) - scan.stamp_s;
      const SE2 motion = T_base_lidar.inverse() * SE2::exp(xi * dt) * T_base_lidar;
      const Eigen::Vector2d predicted = motion * p_lidar;
      check.worst_prediction_error_m =
          std::max(check.worst_prediction_error_m, (*record.p_ref_true[i] - predicted).norm());
      check.largest_distortion_m =
          std::max(check.largest_distortion_m, (*record.p_ref_true[i] - p_lidar).norm());
      ++check.beams;
    }
  }
  return check;
}

TEST(Simulator, KinematicSpinDistortionIsWhatTheRatePredicts) {
  SimConfig c = config(SimMode::kinematic, 360);
  c.duration_s = 3.0;
  const Scenario s = scenario("  - {type: spin, angle_deg: 720, rate_radps: 1.0}\n");
  const SimResult r = simulate(c, squareRoom(3.0), s);
  // The controller turns w = 1 rad/s into wheel rates with the NOMINAL geometry; the true robot
  // moves with J_true * rates: w_true = (b_n / b) (r_R / r_Rn + r_L / r_Ln) / 2 = 1.0377 rad/s,
  // and since r_R / r_Rn != r_L / r_Ln the "spin" also creeps forward at
  // v_true = w b_n (r_R / r_Rn - r_L / r_Ln) / 4 = 4.5 mm/s. Constant after the 0.5 s ramp.
  const Controller controller(s.profile, c.nominalGeometry());
  const Eigen::Vector2d rates = controller.wheelRates(2.0);
  const Eigen::Vector2d twist = c.robot.geometry.twist(rates.x(), rates.y());
  EXPECT_NEAR(twist.y(), 1.0377, 1e-4);
  EXPECT_NEAR(twist.x(), 0.00453, 1e-5);
  const SpinCheck check =
      checkSpin(r.dataset, c.lidar.T_base_lidar, {twist.x(), 0.0, twist.y()}, 0.6, 3.0);
  EXPECT_GT(check.beams, 500u);
  // Kinematic poses are exact arcs: only rounding remains.
  EXPECT_LT(check.worst_prediction_error_m, 1e-9);
  // The distortion itself is real: up to w * 0.1 s * range ~ 0.1 * 3 m at the scan's end.
  EXPECT_GT(check.largest_distortion_m, 0.2);
}

// A lidar mount told wrong (nominal.lidar_mount_error), as wheel radii are: dataset.json tells
// the wrong one and keeps the simulated one as true_lidar_mount, which the scans obey and which
// survives the files; the told mount does not predict the scans' distortion.
TEST(Simulator, AMountToldWrongKeepsTheTrueOneBesideIt) {
  SimConfig c = config(SimMode::kinematic, 360);
  c.duration_s = 3.0;
  applyOverride(c, "nominal.lidar_mount_error.x_m=-0.05");
  applyOverride(c, "nominal.lidar_mount_error.yaw_rad=0.02");
  const Scenario s = scenario("  - {type: spin, angle_deg: 720, rate_radps: 1.0}\n");
  const SimResult r = simulate(c, squareRoom(3.0), s);
  const SE2& truth = c.lidar.T_base_lidar;
  const SE2& told = r.dataset.info.T_base_lidar;
  EXPECT_NEAR(told.x, truth.x - 0.05, 1e-15);
  EXPECT_EQ(told.y, truth.y);
  EXPECT_NEAR(told.yaw, truth.yaw + 0.02, 1e-15);
  ASSERT_TRUE(r.dataset.info.true_T_base_lidar.has_value());
  EXPECT_EQ(r.dataset.info.trueMount().x, truth.x);
  const test::ScratchDir root("sim_told_mount");
  eval::writeDataset(root / "d", r.dataset);
  const Dataset back = eval::readDataset(root / "d");
  EXPECT_EQ(back.info.trueMount().x, truth.x);
  EXPECT_EQ(back.info.T_base_lidar.x, told.x);
  const Controller controller(s.profile, c.nominalGeometry());
  const Eigen::Vector2d rates = controller.wheelRates(2.0);
  const Eigen::Vector3d xi(c.robot.geometry.twist(rates.x(), rates.y()).x(), 0.0,
                           c.robot.geometry.twist(rates.x(), rates.y()).y());
  EXPECT_LT(checkSpin(r.dataset, r.dataset.info.trueMount(), xi, 0.6, 3.0).worst_prediction_error_m,
            1e-9);
  // 5 cm of lever at 1 rad/s over a 0.1 s scan moves a beam by millimetres.
  EXPECT_GT(checkSpin(r.dataset, told, xi, 0.6, 3.0).worst_prediction_error_m, 1e-3);
  // Told right (the default), dataset.json has no true_lidar_mount.
  SimConfig right = config(SimMode::kinematic, 90);
  right.duration_s = 0.5;
  EXPECT_FALSE(simulate(right, squareRoom(3.0), s).dataset.info.true_T_base_lidar.has_value());
}

// A head that turns faster than its scans are published (lidar.sweep_s): each scan's beams span
// the sweep from its stamp, scans stay 1 / rate apart, and the truth's distortion is still what
// the twist predicts at each beam's time (shorter: the sweep is shorter).
TEST(Simulator, AShortSweepTakesTheBeamsFasterThanTheScansArePublished) {
  SimConfig c = config(SimMode::kinematic, 360);
  c.duration_s = 3.0;
  c.lidar.rate_hz = 4.0;
  c.lidar.sweep_s = 0.2;
  const Scenario s = scenario("  - {type: spin, angle_deg: 720, rate_radps: 1.0}\n");
  const SimResult r = simulate(c, squareRoom(3.0), s);
  ASSERT_GE(r.dataset.scans.size(), 11u);
  for (std::size_t k = 1; k < r.dataset.scans.size(); ++k) {
    const LaserScan& scan = r.dataset.scans[k].scan;
    EXPECT_NEAR(scan.stamp_s - r.dataset.scans[k - 1].scan.stamp_s, 0.25, 1e-12);
    EXPECT_NEAR(scan.time_increment_s, 0.2 / 360, 1e-15);
    EXPECT_NEAR(scan.endTime() - scan.stamp_s, 0.2 - 0.2 / 360, 1e-12);
    EXPECT_DOUBLE_EQ(scan.scan_time_s, 0.25);
  }
  const Controller controller(s.profile, c.nominalGeometry());
  const Eigen::Vector2d rates = controller.wheelRates(2.0);
  const Eigen::Vector2d twist = c.robot.geometry.twist(rates.x(), rates.y());
  const SpinCheck check =
      checkSpin(r.dataset, c.lidar.T_base_lidar, {twist.x(), 0.0, twist.y()}, 0.6, 3.0);
  EXPECT_GT(check.beams, 500u);
  EXPECT_LT(check.worst_prediction_error_m, 1e-9);
  // At most w * 0.2 s * the farthest corner, 3 sqrt(2) m: 0.88 m (a 0.25 s sweep: 1.10 m).
  EXPECT_LT(check.largest_distortion_m, 1.0377 * 0.2 * 3.0 * std::sqrt(2.0) * 1.01);
  EXPECT_GT(check.largest_distortion_m, 0.6);
}

// A free-running head (lidar.free_running) published slower than it turns: each scan holds the
// revolution that began nearest its stamp, so its first beam is taken sweep * round(stamp /
// sweep) - stamp from it (a sawtooth within half a revolution), the stamps stay on their grid
// and no two scans share a beam's time.
TEST(Simulator, AFreeRunningHeadPublishesTheRevolutionNearestEachStamp) {
  SimConfig c = config(SimMode::kinematic, 360);
  c.duration_s = 4.0;
  c.lidar.rate_hz = 4.65;
  c.lidar.sweep_s = 0.2;
  c.lidar.free_running = true;
  const Scenario s = scenario("  - {type: spin, angle_deg: 720, rate_radps: 1.0}\n");
  const SimResult r = simulate(c, squareRoom(3.0), s);
  ASSERT_GE(r.dataset.scans.size(), 15u);
  double earliest = 0.0, latest = 0.0;
  for (std::size_t k = 0; k < r.dataset.scans.size(); ++k) {
    const ScanRecord& scan = r.dataset.scans[k];
    const double stamp = double(k) / c.lidar.rate_hz;
    EXPECT_NEAR(scan.scan.stamp_s, stamp, 1e-12);
    const double offset = 0.2 * std::round(stamp / 0.2) - stamp;
    earliest = std::min(earliest, offset), latest = std::max(latest, offset);
    const auto T = r.dataset.groundtruth.at(stamp + offset);
    ASSERT_TRUE(T && scan.T_world_base_true);
    EXPECT_NEAR(normalizeAngle(scan.T_world_base_true->yaw - T->yaw), 0.0, 1e-6) << k;
    if (k > 0) {  // revolutions follow one another: this one starts after the last one ended
      const double previous = double(k - 1) / c.lidar.rate_hz;
      EXPECT_GE(stamp + offset,
                previous + 0.2 * std::round(previous / 0.2) - previous + 0.2 - 1e-9);
    }
  }
  EXPECT_LT(earliest, -0.08);  // the sawtooth covers most of its half-revolution either side
  EXPECT_GT(latest, 0.08);
}

TEST(Simulator, PhysicsSpinDistortionIsWhatTheRatePredicts) {
  SimConfig c = config(SimMode::physics, 360);
  c.duration_s = 2.5;
  const Scenario s = scenario("  - {type: spin, angle_deg: 720, rate_radps: 1.0}\n");
  const SimResult r = simulate(c, squareRoom(3.0), s);
  // The twist Bullet actually reached, from ground truth over the steady part [1.0, 2.5] s.
  const PoseSeries& gt = r.dataset.groundtruth;
  const Eigen::Vector3d xi = between(*gt.at(1.0), *gt.at(2.5)).log() / 1.5;
  const SpinCheck check = checkSpin(r.dataset, c.lidar.T_base_lidar, xi, 1.0, 2.5);
  EXPECT_GT(check.beams, 500u);
  EXPECT_GT(check.largest_distortion_m, 0.2);
  // What remains is the twist's variation inside a scan (motor ripple, contacts). Measured:
  // 8e-10 m (the motors hold the rate exactly once settled). Bound: 0.1 mm, far below the
  // range noise (1 cm) and 3000x below the distortion it explains.
  EXPECT_LT(check.worst_prediction_error_m, 1e-4);
  RecordProperty("spin_prediction_error_m", std::to_string(check.worst_prediction_error_m));
  std::printf("physics spin: worst prediction error %.3g m, largest distortion %.3g m\n",
              check.worst_prediction_error_m, check.largest_distortion_m);
}

// ---- Odometry against ground truth -------------------------------------------------------------

TEST(Simulator, KinematicTrueGeometryOdometryReproducesGroundTruthToQuantisation) {
  SimConfig c = config(SimMode::kinematic, 8);
  const Scenario s = scenario("  - {type: figure_eight, radius_m: 0.5, speed_mps: 0.5}\n");
  const SimResult r = simulate(c, squareRoom(3.0), s);
  const Dataset& d = r.dataset;
  const PoseSeries odom = integrateEncoders(d.encoders, c.robot.geometry, 4096);
  // Floor quantisation leaves each wheel angle short by e in [0, delta), delta = 2 pi / 4096.
  // Heading is linear in the wheel angles, theta = (r_R phi_R - r_L phi_L) / b, so its error
  // never accumulates: |e_theta| < max(r) delta / b. Position errors integrate the heading
  // error along the path: |e_p| < |e_theta|max * s + r delta, s the distance so far.
  const double delta = tickAngle(c);
  const double heading_bound = 0.1 * delta / 0.5;
  double s_m = 0.0, worst_heading = 0.0, worst_ratio = 0.0;
  for (std::size_t k = 1; k < odom.size(); ++k) {
    const double t = odom[k].stamp_s;
    const SE2 truth = *d.groundtruth.at(t);
    s_m += (truth.translation() - d.groundtruth.at(odom[k - 1].stamp_s)->translation()).norm();
    const double e_theta = std::abs(normalizeAngle(odom[k].value.yaw - truth.yaw));
    const double e_p = (odom[k].value.translation() - truth.translation()).norm();
    worst_heading = std::max(worst_heading, e_theta);
    worst_ratio = std::max(worst_ratio, e_p / (heading_bound * s_m + 0.1 * delta));
  }
  EXPECT_LT(worst_heading, heading_bound);
  EXPECT_LT(worst_ratio, 1.0);
  EXPECT_GT(s_m, 6.0);  // two circles of 2 pi 0.5 m
  EXPECT_LT(r.summary.drift_true.max_position_error_m, heading_bound * s_m + 0.1 * delta);
}

/// Drift of nominal odometry after one constant-curvature segment commanding (D, Theta): the
/// odometry inverts the controller (both use the nominal geometry), so it reports exactly the
/// commanded arc exp(D, 0, Theta); the truth is the arc J_true J_nominal^-1 (D, Theta). Both
/// components of every trapezoid scale together, so each motion is a single arc.
struct PredictedDrift {
  double final_position_m = 0.0;   ///< |p_odom(end) - p_true(end)|
  double final_heading_rad = 0.0;  ///< yaw_odom(end) - yaw_true(end), wrapped
};

PredictedDrift predictedDrift(const SimConfig& c, double D, double theta) {
  const Eigen::Vector2d phi = c.nominalGeometry().wheelRates(D, theta);  // J_n^-1: wheel angles
  const Eigen::Vector2d truth = c.robot.geometry.twist(phi.x(), phi.y());
  const SE2 odom_end = SE2::exp({D, 0.0, theta});
  const SE2 true_end = SE2::exp({truth.x(), 0.0, truth.y()});
  PredictedDrift drift;
  drift.final_position_m = (odom_end.translation() - true_end.translation()).norm();
  drift.final_heading_rad = normalizeAngle(theta - truth.y());
  return drift;
}

TEST(Simulator, KinematicNominalDriftMatchesTheGeometryErrors) {
  const SimConfig c = config(SimMode::kinematic, 8);
  // Tick quantisation: heading error < max(r) delta / b (see above); position error < heading
  // error times distance plus r delta per wheel.
  const double heading_tol = 0.1 * tickAngle(c) / 0.5;
  {
    // Spin by Theta = 2 pi: the true robot turns k Theta, k = (b_n / b) (k_R + k_L) / 2 = 1.0377
    // (k_i = r_i / r_i,nominal), i.e. 13.6 deg too far, and creeps 0.45 mm per rad.
    const SimResult r =
        simulate(c, squareRoom(3.0), scenario("  - {type: spin, angle_deg: 360}\n"));
    const PredictedDrift p = predictedDrift(c, 0.0, 2.0 * std::numbers::pi);
    EXPECT_NEAR(p.final_heading_rad, -0.23702, 1e-5);
    EXPECT_NEAR(r.summary.drift_nominal.final_error.yaw, p.final_heading_rad, heading_tol);
    EXPECT_NEAR(r.summary.drift_nominal.final_position_error_m, p.final_position_m,
                2 * 0.1 * tickAngle(c));
  }
  {
    // Straight D = 2 m: the truth is an arc of length D (k_L + k_R) / 2 turning
    // D (k_R - k_L) / b = 0.139 rad (8 deg); it ends 0.139 m from the odometry's (2, 0).
    const SimResult r = simulate(
        c, squareRoom(3.0), scenario("  - {type: straight, distance_m: 2.0, speed_mps: 0.5}\n"));
    const PredictedDrift p = predictedDrift(c, 2.0, 0.0);
    EXPECT_NEAR(p.final_heading_rad, -0.1393, 1e-4);
    EXPECT_NEAR(p.final_position_m, 0.1392, 1e-4);
    EXPECT_NEAR(r.summary.drift_nominal.final_error.yaw, p.final_heading_rad, heading_tol);
    EXPECT_NEAR(r.summary.drift_nominal.final_position_error_m, p.final_position_m,
                heading_tol * 2.0 + 2 * 0.1 * tickAngle(c));
  }
}

TEST(Simulator, PhysicsFigureEightTrueGeometryOdometryStaysCloseToTruth) {
  SimConfig c = config(SimMode::physics, 8);
  const Scenario s = scenario("  - {type: figure_eight, radius_m: 0.5, speed_mps: 0.5}\n");
  const SimResult r = simulate(c, squareRoom(3.0), s);
  // Rigid wheels roll at their radius; what remains is contact slip during the ramps and flips
  // plus quantisation (kinematic bound above: 3e-4 rad * 6.3 m = 2 mm). Measured on this run:
  // max position error 1.16 mm, final heading error -9e-6 rad with 50 solver iterations; 1.42 mm
  // and 5.5e-4 rad with the default 10 iterations and relaxation 1.5. Bounds: 5 mm and 1e-3 rad.
  EXPECT_LT(r.summary.drift_true.max_position_error_m, 0.005);
  EXPECT_LT(std::abs(r.summary.drift_true.final_error.yaw), 1e-3);
  // The wrong geometry dominates by far.
  EXPECT_GT(r.summary.drift_nominal.max_position_error_m,
            5 * r.summary.drift_true.max_position_error_m);
  RecordProperty("drift_true_max_m", std::to_string(r.summary.drift_true.max_position_error_m));
  RecordProperty("drift_true_final_heading_rad",
                 std::to_string(r.summary.drift_true.final_error.yaw));
  RecordProperty("drift_nominal_max_m",
                 std::to_string(r.summary.drift_nominal.max_position_error_m));
}

// ---- The dataset -------------------------------------------------------------------------------

TEST(Simulator, DatasetHasEverySensorAtItsRate) {
  SimConfig c = config(SimMode::kinematic, 90);
  c.duration_s = 1.25;
  const SimResult r = simulate(
      c, squareRoom(3.0), scenario("  - {type: arc, v_mps: 0.4, w_radps: 0.8, duration_s: 4}\n"));
  const Dataset& d = r.dataset;
  EXPECT_EQ(d.groundtruth.size(), 1251u);  // t = 0 and every 1 ms step
  EXPECT_EQ(d.encoders.size(), 126u);      // 0, 10 ms, ..., 1.25 s
  EXPECT_EQ(d.imu.size(), 251u);
  EXPECT_EQ(d.odom_nominal.size(), d.encoders.size());
  ASSERT_EQ(d.scans.size(), 12u);  // stamps 0 .. 1.1 s; the scan from 1.2 s is incomplete
  for (std::size_t j = 0; j < d.scans.size(); ++j) {
    const ScanRecord& s = d.scans[j];
    EXPECT_DOUBLE_EQ(s.scan.stamp_s, 0.1 * j);
    EXPECT_EQ(s.scan.size(), 90u);
    EXPECT_EQ(s.p_ref_true.size(), 90u);
    ASSERT_TRUE(s.T_world_base_true && s.T_odom_base_nominal);
    EXPECT_NEAR((s.T_world_base_true->vector() - d.groundtruth.at(s.scan.stamp_s)->vector()).norm(),
                0.0, 1e-12);
    for (std::size_t i = 0; i < s.scan.size(); ++i) {
      EXPECT_EQ(std::isfinite(s.scan.ranges_m[i]), s.p_ref_true[i].has_value());
    }
  }
  ASSERT_TRUE(d.scans[0].p_ref_true[0]);  // beam 0 is the reference: p_ref = p_L
  EXPECT_LT((*d.scans[0].p_ref_true[0] - d.scans[0].scan.point(0)).norm(), 1e-12);
  EXPECT_EQ(d.info.ticks_per_revolution, 4096);
  EXPECT_EQ(d.info.nominal_geometry.wheel_base_m, c.nominalGeometry().wheel_base_m);
  EXPECT_EQ(d.info.config["mode"], "kinematic");
  // IMU on the steady arc (after the 0.4 s ramp): gyro = w_true + bias, accel_y = v w
  // (centripetal).
  const Eigen::Vector2d rates = Controller(scenario("  - {type: arc, v_mps: 0.4, w_radps: 0.8, "
                                                    "duration_s: 4}\n")
                                               .profile,
                                           c.nominalGeometry())
                                    .wheelRates(1.0);
  const Eigen::Vector2d twist = c.robot.geometry.twist(rates.x(), rates.y());
  double gyro = 0.0, accel_y = 0.0;
  int n = 0;
  for (const ImuSample& s : d.imu) {
    if (s.stamp_s <= 0.5) continue;
    gyro += s.gyro_z_radps;
    accel_y += s.accel_y_mps2;
    ++n;
  }
  // Means of n = 150 samples: noise sigma / sqrt(n) = 1.6e-4 rad/s and 1.6e-3 m/s^2; 4 sigma.
  EXPECT_NEAR(gyro / n, twist.y() + c.imu.gyro_bias_radps, 4 * 0.002 / std::sqrt(n));
  EXPECT_NEAR(accel_y / n, twist.x() * twist.y() + c.imu.accel_bias_y_mps2,
              4 * 0.02 / std::sqrt(n) + 1e-3);
}

// A run that ends just before a scan's last beam reaches the next encoder sample: with 10 Hz,
// 90 beams and 100 Hz encoders, the scan from 1.0 s completes at 1.0 + 89/900 = 1.0989 s, after
// the last encoder sample (1.09 s) of a 1.0995 s run. The odometry does not cover that scan, so
// the simulator drops it and the dataset stays readable.
TEST(Simulator, DropsAFinalScanTheEncodersDoNotCover) {
  SimConfig c = config(SimMode::kinematic, 90);
  c.duration_s = 1.0995;
  const SimResult r = simulate(
      c, squareRoom(3.0), scenario("  - {type: arc, v_mps: 0.4, w_radps: 0.8, duration_s: 4}\n"));
  const Dataset& d = r.dataset;
  ASSERT_NEAR(d.encoders.back().stamp_s, 1.09, 1e-12);
  ASSERT_EQ(d.scans.size(), 10u);  // stamps 0 .. 0.9 s; 1.0 s would end at 1.0989 s
  EXPECT_LE(d.scans.back().scan.endTime(), d.encoders.back().stamp_s);
  const test::ScratchDir scratch("sim_last_scan");
  const auto dir = scratch / "data";
  eval::writeDataset(dir, d);
  EXPECT_EQ(eval::readDataset(dir).scans.size(), 10u);
}

/// Every file of dataset folder `a` (at least the six a run writes) has the bytes of b's.
void expectSameFiles(const std::filesystem::path& a, const std::filesystem::path& b) {
  std::size_t files = 0;
  for (const auto& entry : std::filesystem::directory_iterator(a)) {
    const auto name = entry.path().filename();
    SCOPED_TRACE(name.string());
    EXPECT_EQ(slurp(a / name), slurp(b / name));
    ++files;
  }
  EXPECT_GE(files, 6u);
}

TEST(Simulator, SameSeedGivesIdenticalBytes) {
  const test::ScratchDir root("sim_determinism");
  SimConfig c = config(SimMode::physics, 180);
  c.duration_s = 1.5;
  const Scenario s = scenario("  - {type: figure_eight, radius_m: 0.5, speed_mps: 0.5}\n");
  c.seed = 5;
  eval::writeDataset(root / "a", simulate(c, squareRoom(3.0), s).dataset);
  eval::writeDataset(root / "b", simulate(c, squareRoom(3.0), s).dataset);
  c.seed = 6;
  eval::writeDataset(root / "c", simulate(c, squareRoom(3.0), s).dataset);
  expectSameFiles(root / "a", root / "b");
  // Another seed changes the sensor noise and nothing else: physics ignores the seed.
  EXPECT_NE(slurp(root / "a" / "scans.jsonl"), slurp(root / "c" / "scans.jsonl"));
  EXPECT_NE(slurp(root / "a" / "imu.csv"), slurp(root / "c" / "imu.csv"));
  EXPECT_EQ(slurp(root / "a" / "groundtruth.tum"), slurp(root / "c" / "groundtruth.tum"));
  EXPECT_EQ(slurp(root / "a" / "encoders.csv"), slurp(root / "c" / "encoders.csv"));
}

// A run that changes only its sensors replays the recorded motion and writes the bytes a fresh
// physics run writes; a change to the robot steps the physics again and records that motion.
TEST(Simulator, AReplayedMotionGivesTheBytesOfAFreshRun) {
  const test::ScratchDir root("sim_replay");
  SimConfig c = config(SimMode::physics, 180);
  c.duration_s = 1.5;
  const Scenario s = scenario("  - {type: figure_eight, radius_m: 0.5, speed_mps: 0.5}\n");
  RecordedMotion motion;
  simulate(c, squareRoom(3.0), s, motion);
  const std::string key = motion.key;
  ASSERT_EQ(motion.states.size(), 1u + static_cast<std::size_t>(1.5 * c.physics_rate_hz));
  c.lidar.range_noise_m = 0.03;  // the sensors only
  c.encoders.slip_sigma = 0.05;
  EXPECT_EQ(motionKey(c), key);
  eval::writeDataset(root / "replayed", simulate(c, squareRoom(3.0), s, motion).dataset);
  eval::writeDataset(root / "fresh", simulate(c, squareRoom(3.0), s).dataset);
  expectSameFiles(root / "fresh", root / "replayed");
  c.robot.geometry.wheel_base_m *= 1.1;  // the motion: stepped again, and recorded
  EXPECT_NE(motionKey(c), key);
  const SimResult wider = simulate(c, squareRoom(3.0), s, motion);
  EXPECT_EQ(motion.key, motionKey(c));
  EXPECT_EQ(motion.states.back().T_world_base.yaw,
            wider.dataset.groundtruth.samples().back().value.yaw);
}

// ---- Refusals ----------------------------------------------------------------------------------

TEST(Simulator, ScenarioLeavingTheWorldIsRefusedBeforeSimulating) {
  const SimConfig c = config(SimMode::physics);
  try {
    simulate(c, squareRoom(3.0),
             scenario("  - {type: spin, angle_deg: 90}\n"
                      "  - {type: straight, distance_m: 8.0}\n"));
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("test_scenario.yaml:3: segments[1] (straight)"), std::string::npos) << what;
    EXPECT_NE(what.find("leave the free space"), std::string::npos) << what;
  }
  World tight = squareRoom(0.2);  // the footprint alone does not fit
  EXPECT_THROW(simulate(c, tight, scenario("  - {type: stop, duration_s: 1}\n")), InputError);
}

TEST(Simulator, ShippedScenariosFitTheDefaultWorld) {
  const std::filesystem::path root(SLAMPREP_SOURCE_DIR);
  const World room = loadWorld(root / "worlds" / "room.yaml");
  const Scene scene(room);
  const SimConfig c;
  for (const char* name : {"umbmark_cw", "umbmark_ccw", "arc", "figure_eight", "spin", "straight",
                           "stop_and_go", "random_smooth", "default"}) {
    SCOPED_TRACE(name);
    const Scenario s = loadScenario(root / "worlds" / "scenarios" / (std::string(name) + ".yaml"));
    EXPECT_NO_THROW(checkPathInWorld(scene, s, c, room.T_world_start, s.profile.duration_s()));
  }
}

TEST(Simulator, InvalidConfigurationIsRefused) {
  SimConfig c = config(SimMode::kinematic);
  c.robot.geometry.radius_left_m = -0.1;
  try {
    simulate(c, squareRoom(3.0), scenario("  - {type: stop, duration_s: 1}\n"));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("robot.radius_left_m"), std::string::npos);
  }
}

}  // namespace
}  // namespace slamprep::sim
