#include "slamprep/algo/deskew/deskew.hpp"

#include <gtest/gtest.h>

#include <set>

#include "slamprep/eval/metrics/deskew_error.hpp"
#include "slamprep/tests/algo_deskew/synthetic_world.hpp"

namespace slamprep::algo {
namespace {

using namespace slamprep::testing;

const SE2 kTbaseLidar(0.12, -0.03, 0.05);

struct Scenario {
  PoseSeries truth;  // T_world_base at the 1 kHz "physics" rate
  SyntheticScan synth;
};

/// One 10 Hz, 720-beam scan starting at t = 1.0 s, cast while the robot follows `motion`.
Scenario makeScenario(const Motion& motion, const LidarConfig& cfg = {}) {
  Scenario s;
  s.truth = sampleTruth(motion, 0.0, 2.0, 1e-3);
  s.synth = castScan(roomWorld(), s.truth, kTbaseLidar, 1.0, cfg);
  return s;
}

Motion constantVelocity() {
  return {SE2(-0.5, -0.3, 0.2), 1.0, 1.0, 0.0, 0.0};
}
Motion constantAcceleration() {
  return {SE2(-0.5, -0.3, 0.2), 0.2, -0.5, 2.0, 4.0};
}

DeskewInputs inputFor(const Scenario& s, const PoseSeries& odometry = {}) {
  DeskewInputs in;
  in.odometry = odometry;
  in.groundtruth = s.truth;
  in.T_base_lidar = kTbaseLidar;
  return in;
}

double maxError(const DeskewResult& r, const SyntheticScan& synth) {
  return eval::deskewError(r.p_ref, synth.p_ref_true).error_m.max;
}

/// Largest ratio |error_i| / (e_pos + (r_i + 0.2 m) e_yaw) over the beams: the per-beam bound of
/// a relative pose T_ref^-1 T_i whose two poses each err by at most e_pos and e_yaw (0.2 m covers
/// the lidar's own travel during the scan and its mount offset).
double worstBoundRatio(const DeskewResult& r, const SyntheticScan& synth, double e_pos_m,
                       double e_yaw_rad) {
  double worst = 0.0;
  for (std::size_t i = 0; i < r.p_ref.size(); ++i) {
    if (!r.p_ref[i] || !synth.p_ref_true[i]) continue;
    const double bound = e_pos_m + (synth.p_ref_true[i]->norm() + 0.2) * e_yaw_rad;
    worst = std::max(worst, (*r.p_ref[i] - *synth.p_ref_true[i]).norm() / bound);
  }
  return worst;
}

TEST(DeskewNames, RoundTripAndCliSpelling) {
  const std::vector<std::string> expected = {"none", "oracle",      "const-velocity",
                                             "vicp", "odom-linear", "odom-quadratic",
                                             "imu",  "odom-icp"};
  ASSERT_EQ(allDeskewMethods().size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) {
    EXPECT_EQ(deskewMethodName(allDeskewMethods()[i]), expected[i]);
    EXPECT_EQ(parseDeskewMethod(expected[i]), allDeskewMethods()[i]);
  }
  EXPECT_FALSE(parseDeskewMethod("linear"));
  EXPECT_EQ(parseReferenceTime("middle"), ReferenceTime::kMiddle);
  EXPECT_FALSE(parseReferenceTime("centre"));
}

// The oracle uses the very poses that distorted the scan: only rounding remains (1e-9 m is
// ~1e6 roundings of 6 m ranges).
TEST(DeskewOracle, RestoresConstantVelocityAndAccelerationTo1e9) {
  for (const Motion& m : {constantVelocity(), constantAcceleration()}) {
    const Scenario s = makeScenario(m);
    const DeskewResult none = deskew(DeskewMethod::kNone, s.synth.scan, inputFor(s), {});
    const DeskewResult oracle = deskew(DeskewMethod::kOracle, s.synth.scan, inputFor(s), {});
    ASSERT_TRUE(oracle.ok) << oracle.reason;
    EXPECT_LT(maxError(oracle, s.synth), 1e-9);
    EXPECT_GT(eval::deskewError(none.p_ref, s.synth.p_ref_true).error_m.mean,
              0.01);  // there was distortion
  }
}

// Noiseless odometry at 100 Hz (h = 10 ms), not aligned with the scan. Geodesic interpolation is
// exact for a constant twist, so under constant velocity odom-linear is exact to rounding.
// Under a twist changing at rate (a, alpha) the interpolation error over one sample interval is
// s (h - s) / 2 * (a, alpha), at most h^2/8 (a, alpha): e_pos = a h^2/8, e_yaw = alpha h^2/8,
// with the O(h^3) commutator terms (~1e-7 here) covered by asserting a ratio below 2 (the
// relative pose T_ref^-1 T_i has two interpolated poses).
TEST(DeskewOdometry, LinearWithinInterpolationBound) {
  {
    const Scenario s = makeScenario(constantVelocity());
    const PoseSeries odom = resample(s.truth, 0.0037, 2.0, 100.0, SE2(3.0, -1.0, 0.7));
    const DeskewResult r = deskew(DeskewMethod::kOdomLinear, s.synth.scan, inputFor(s, odom), {});
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_LT(maxError(r, s.synth), 1e-9);
  }
  const Motion m = constantAcceleration();
  const Scenario s = makeScenario(m);
  const PoseSeries odom = resample(s.truth, 0.0037, 2.0, 100.0, SE2(3.0, -1.0, 0.7));
  const double h = 0.01;
  const DeskewResult r = deskew(DeskewMethod::kOdomLinear, s.synth.scan, inputFor(s, odom), {});
  ASSERT_TRUE(r.ok) << r.reason;
  const double ratio =
      worstBoundRatio(r, s.synth, m.a_mps2 * h * h / 8, m.alpha_radps2 * h * h / 8);
  EXPECT_LT(ratio, 2.0);
  EXPECT_GT(ratio, 0.05);  // the bound is not vacuous: errors reach a real fraction of it
}

// The lecture's premise for the quadratic: slow odometry (20 Hz, h = 50 ms) synchronised with
// the scan, so p_s, p_m, p_e are (nearly) odometry samples. Under constant acceleration the yaw
// is exactly quadratic, positions have a cubic term |p'''| <= v w^2 + 3 a w + v alpha ~ 16 m/s^3
// here, giving |p'''| T^3 sqrt(3)/216 = 1.3e-4 m for T = 0.1 s; the k = 4 geodesic pieces add
// (a, alpha) (T/k)^2/8. Linear interpolation at 20 Hz errs by (a, alpha) h^2/8: 4x more.
TEST(DeskewOdometry, QuadraticBeatsLinearUnderConstantAcceleration) {
  const Motion m = constantAcceleration();
  const Scenario s = makeScenario(m);
  const PoseSeries odom = resample(s.truth, 0.0, 2.0, 20.0);
  const DeskewResult lin = deskew(DeskewMethod::kOdomLinear, s.synth.scan, inputFor(s, odom), {});
  const DeskewResult quad =
      deskew(DeskewMethod::kOdomQuadratic, s.synth.scan, inputFor(s, odom), {});
  ASSERT_TRUE(lin.ok && quad.ok) << lin.reason << quad.reason;
  const double T = 0.1, k = 4, h = 0.05;
  const double cubic = 16.0 * T * T * T * std::sqrt(3.0) / 216.0;
  EXPECT_LT(worstBoundRatio(quad, s.synth, cubic + m.a_mps2 * (T / k) * (T / k) / 8,
                            m.alpha_radps2 * (T / k) * (T / k) / 8),
            2.0);
  EXPECT_LT(worstBoundRatio(lin, s.synth, m.a_mps2 * h * h / 8, m.alpha_radps2 * h * h / 8), 2.0);
  const double mean_lin = eval::deskewError(lin.p_ref, s.synth.p_ref_true).error_m.mean;
  const double mean_quad = eval::deskewError(quad.p_ref, s.synth.p_ref_true).error_m.mean;
  EXPECT_LT(2.0 * mean_quad, mean_lin) << mean_quad << " vs " << mean_lin;
}

// The gyro gives the rotation exactly (yaw rate linear in time, trapezoid integration exact),
// so with 20 Hz odometry the IMU method keeps only odometry's translation error a h^2/8.
TEST(DeskewImu, GyroRotationBeatsSlowOdometry) {
  const Motion m = constantAcceleration();
  const Scenario s = makeScenario(m);
  const PoseSeries odom = resample(s.truth, 0.0, 2.0, 20.0);
  ImuLog imu;
  for (int k = 0; k <= 400; ++k) {  // 200 Hz, noiseless
    const double t = k * 0.005;
    imu.push_back({t, m.w0_radps + m.alpha_radps2 * t, 0.0, 0.0});
  }
  DeskewInputs in = inputFor(s, odom);
  in.imu = imu;
  const DeskewResult r = deskew(DeskewMethod::kImu, s.synth.scan, in, {});
  ASSERT_TRUE(r.ok) << r.reason;
  const DeskewResult lin = deskew(DeskewMethod::kOdomLinear, s.synth.scan, in, {});
  const double h = 0.05;
  // Rotation: exact up to the 1 kHz truth's own piecewise-constant twist, alpha (1 ms)^2 / 8.
  EXPECT_LT(worstBoundRatio(r, s.synth, m.a_mps2 * h * h / 8, m.alpha_radps2 * 1e-6 / 8), 2.0);
  EXPECT_LT(5.0 * eval::deskewError(r.p_ref, s.synth.p_ref_true).error_m.mean,
            eval::deskewError(lin.p_ref, s.synth.p_ref_true).error_m.mean);
}

// A clockwise lidar is the mirror image of a counterclockwise one: mirror the world (y -> -y),
// the motion (y, yaw, w -> negated) and the mount, and every beam sees the mirrored point at the
// same time. The corrected points must be each other's mirror images.
TEST(DeskewConventions, ClockwiseEqualsMirroredCounterclockwise) {
  const Motion m = constantAcceleration();
  Motion mirrored = m;
  mirrored.T_world_base0 = SE2(m.T_world_base0.x, -m.T_world_base0.y, -m.T_world_base0.yaw);
  mirrored.w0_radps = -m.w0_radps;
  mirrored.alpha_radps2 = -m.alpha_radps2;
  auto world_m = roomWorld();
  for (auto& seg : world_m) seg.a.y() *= -1, seg.b.y() *= -1;
  const SE2 mount_m(kTbaseLidar.x, -kTbaseLidar.y, -kTbaseLidar.yaw);
  const PoseSeries truth = sampleTruth(m, 0.0, 2.0, 1e-3),
                   truth_m = sampleTruth(mirrored, 0.0, 2.0, 1e-3);
  LidarConfig ccw, cw;
  cw.clockwise = true;
  cw.angle_min_rad = -ccw.angle_min_rad;
  const auto scan = castScan(roomWorld(), truth, kTbaseLidar, 1.0, ccw);
  const auto scan_m = castScan(world_m, truth_m, mount_m, 1.0, cw);
  const PoseSeries odom = resample(truth, 0.0, 2.0, 50.0),
                   odom_m = resample(truth_m, 0.0, 2.0, 50.0);
  for (DeskewMethod method : {DeskewMethod::kOdomLinear, DeskewMethod::kOdomQuadratic}) {
    DeskewInputs a, b;
    a.odometry = odom, a.T_base_lidar = kTbaseLidar;
    b.odometry = odom_m, b.T_base_lidar = mount_m;
    const DeskewResult ra = deskew(method, scan.scan, a, {}),
                       rb = deskew(method, scan_m.scan, b, {});
    ASSERT_TRUE(ra.ok && rb.ok);
    std::size_t compared = 0;
    for (std::size_t i = 0; i < ra.p_ref.size(); ++i) {
      ASSERT_EQ(ra.p_ref[i].has_value(), rb.p_ref[i].has_value()) << i;
      if (!ra.p_ref[i]) continue;
      const Eigen::Vector2d mirror(rb.p_ref[i]->x(), -rb.p_ref[i]->y());
      EXPECT_LT((*ra.p_ref[i] - mirror).norm(), 1e-9) << i;  // ray casting and trig rounding
      ++compared;
    }
    EXPECT_GT(compared, 700u);
    // Repacked scans: same ranges on the mirrored grid (bin i of one is bin i of the other).
    for (std::size_t i = 0; i < ra.repacked.size(); ++i)
      if (std::isfinite(ra.repacked.ranges_m[i])) {
        EXPECT_NEAR(ra.repacked.ranges_m[i], rb.repacked.ranges_m[i], 1e-9) << i;
      }
  }
}

// A driver that stamps the last beam: the same measurements with stamp = t_last. With the flag
// the result is identical; without it the odometry check names the likely cause.
TEST(DeskewConventions, LastBeamStampEqualsFirstBeamStamp) {
  const Scenario s = makeScenario(constantAcceleration());
  const PoseSeries odom = resample(s.truth, 0.0, 1.1, 100.0);  // ends 1 ms after the scan
  LaserScan last = s.synth.scan;
  last.stamp_s = s.synth.scan.endTime();
  DeskewInputs first_in = inputFor(s, odom), last_in = first_in;
  last_in.stamp_is_last_beam = true;
  for (ReferenceTime ref : {ReferenceTime::kFirst, ReferenceTime::kMiddle, ReferenceTime::kLast}) {
    first_in.reference = last_in.reference = ref;
    const DeskewResult a = deskew(DeskewMethod::kOdomLinear, s.synth.scan, first_in, {});
    const DeskewResult b = deskew(DeskewMethod::kOdomLinear, last, last_in, {});
    ASSERT_TRUE(a.ok && b.ok) << a.reason << b.reason;
    EXPECT_NEAR(a.reference_s, b.reference_s, 1e-12);
    for (std::size_t i = 0; i < a.p_ref.size(); ++i)
      if (a.p_ref[i]) {
        EXPECT_LT((*a.p_ref[i] - *b.p_ref[i]).norm(), 1e-9) << i;
      }
  }
  // Forgetting the flag: the scan seems to end 0.1 s after the odometry does.
  DeskewInputs wrong = last_in;
  wrong.stamp_is_last_beam = false;
  const DeskewResult r = deskew(DeskewMethod::kOdomLinear, last, wrong, {});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("does not bracket"), std::string::npos) << r.reason;
  EXPECT_NE(r.reason.find("set stamp_is_last_beam"), std::string::npos) << r.reason;
  EXPECT_EQ(deskewRefusalName(r.refusal), "not-bracketed");
}

// Other reference times: the points of reference R are the first-beam points moved by the true
// T_R_first; checked against the oracle's own first-beam result.
TEST(DeskewConventions, ReferenceTimesAreConsistent) {
  const Scenario s = makeScenario(constantAcceleration());
  DeskewInputs in = inputFor(s);
  const DeskewResult first = deskew(DeskewMethod::kOracle, s.synth.scan, in, {});
  in.reference = ReferenceTime::kLast;
  const DeskewResult last = deskew(DeskewMethod::kOracle, s.synth.scan, in, {});
  ASSERT_TRUE(first.ok && last.ok);
  EXPECT_NEAR(last.reference_s, s.synth.scan.endTime(), 1e-12);
  EXPECT_EQ(last.repacked.stamp_s, last.reference_s);
  EXPECT_EQ(last.repacked.time_increment_s, 0.0);
  const SE2 T_last_first =
      between(*s.truth.at(last.reference_s) * kTbaseLidar, *s.truth.at(1.0) * kTbaseLidar);
  EXPECT_LT((last.T_first_ref.inverse().vector() - T_last_first.vector()).norm(), 1e-12);
  for (std::size_t i = 0; i < first.p_ref.size(); ++i)
    if (first.p_ref[i]) {
      EXPECT_LT((*last.p_ref[i] - T_last_first * *first.p_ref[i]).norm(), 1e-9);
    }
}

TEST(DeskewRefusals, EveryReasonHasItsOwnName) {
  std::set<std::string_view> names;
  for (const DeskewRefusal r : allDeskewRefusals()) names.insert(deskewRefusalName(r));
  EXPECT_EQ(names.size(), allDeskewRefusals().size());
  EXPECT_EQ(names.count(""), 0u);
  EXPECT_EQ(deskewRefusalName(DeskewRefusal::kNone), "");
}

TEST(DeskewRefusals, SaysWhy) {
  const Scenario s = makeScenario(constantVelocity());
  // time_increment = 0: beam times unknown.
  LaserScan flat = s.synth.scan;
  flat.time_increment_s = 0.0;
  const DeskewInputs in = inputFor(s);
  DeskewResult r = deskew(DeskewMethod::kNone, flat, in, {});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("time_increment"), std::string::npos);
  EXPECT_EQ(deskewRefusalName(r.refusal), "no-beam-times");
  // Missing inputs.
  r = deskew(DeskewMethod::kOdomLinear, s.synth.scan, inputFor(s), {});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("needs odometry"), std::string::npos) << r.reason;
  EXPECT_EQ(deskewRefusalName(r.refusal), "missing-input");
  r = deskew(DeskewMethod::kVicp, s.synth.scan, inputFor(s), {});
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.refusal, DeskewRefusal::kMissingInput);
  // An odometry gap of 0.3 s across the scan: refused, not interpolated across.
  PoseSeries gappy;
  const PoseSeries dense = resample(s.truth, 0.0, 2.0, 100.0);
  for (const auto& x : dense.samples())
    if (x.stamp_s < 0.95 || x.stamp_s > 1.25) gappy.push_back(x.stamp_s, x.value);
  r = deskew(DeskewMethod::kOdomQuadratic, s.synth.scan, inputFor(s, gappy), {});
  EXPECT_FALSE(r.ok);
  EXPECT_NE(r.reason.find("gap"), std::string::npos) << r.reason;
  EXPECT_EQ(deskewRefusalName(r.refusal), "sample-gap");
  EXPECT_TRUE(r.p_ref.empty());
  // No NaN anywhere for an all-no-return scan.
  LaserScan empty_returns = s.synth.scan;
  std::fill(empty_returns.ranges_m.begin(), empty_returns.ranges_m.end(),
            std::numeric_limits<double>::infinity());
  r = deskew(DeskewMethod::kOracle, empty_returns, in, {});
  ASSERT_TRUE(r.ok);
  for (const auto& p : r.p_ref) EXPECT_FALSE(p);
}

}  // namespace
}  // namespace slamprep::algo
