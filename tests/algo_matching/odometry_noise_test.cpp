// The odometry's noise measured against the scans (algo/matching/odometry_noise.hpp): a drive
// whose scans sit at the truth and whose odometry steps carry known Gaussian noise, with a
// second kind of scan the map explains badly and whose poses are far off.
#include "slamprep/algo/matching/odometry_noise.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <random>

namespace slamprep::algo {
namespace {

struct Drive {
  KeyframeOdometry scans_alone;
  std::vector<StepPrior> priors;
};

/// n scans along a gentle curve; odometry steps = true steps with N(0, sigma_m) per axis and
/// N(0, sigma_rad) in yaw. The scans `bad` picks (support `bad_support`) are placed `bad_offset`
/// off the truth, the rest exactly at it (support 0.99).
Drive drive(
    std::size_t n, double sigma_m, double sigma_rad, double bad_support, const SE2& bad_offset,
    unsigned seed,
    const std::function<bool(std::size_t)>& bad = [](std::size_t) { return false; }) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);  // a 0 sigma is not a normal_distribution's
  const SE2 step(0.1, 0.0, 0.01);
  Drive d;
  SE2 truth;
  d.priors.resize(n);
  for (std::size_t k = 0; k < n; ++k) {
    if (k > 0) {
      truth = truth * step;
      const double ex = sigma_m * unit(rng), ey = sigma_m * unit(rng);
      d.priors[k].odometry = SE2(step.x + ex, step.y + ey, step.yaw + sigma_rad * unit(rng));
    }
    TrackedScan scan;
    scan.T_world_lidar = bad(k) ? truth * bad_offset : truth;
    scan.support.overlapping = 100;
    scan.support.inliers = static_cast<std::size_t>(100 * (bad(k) ? bad_support : 0.99));
    d.scans_alone.scans.push_back(scan);
  }
  return d;
}

// Eqs. 2-3 recover the odometry's sigmas from the scans the map explains best; the badly
// explained 40 % (runs of 40 scans, 0.5 m and 10 degrees off) do not enter. The steps into a
// good run from a bad one (1 in 60) still do: the median moves by about 2 %. 2400 steps: the
// MAD's standard error is about 3 %, so 12 % is four of them.
TEST(OdometryNoise, IsMeasuredOnTheScansTheMapExplainsBest) {
  const double sigma_m = 0.02, sigma_rad = 0.005;
  const auto bad = [](std::size_t k) { return k % 100 >= 60; };
  const Drive d = drive(4001, sigma_m, sigma_rad, 0.5, SE2(0.5, 0.0, 0.17), 7, bad);
  const auto noise = measureOdometryNoise(d.scans_alone, d.priors);
  ASSERT_TRUE(noise);
  EXPECT_NEAR(noise->sigma_rad, sigma_rad, 0.12 * sigma_rad);
  EXPECT_NEAR(noise->sigma_m, sigma_m, 0.12 * sigma_m);
  EXPECT_NEAR(noise->min_support, 0.99, 1e-12);
  EXPECT_EQ(noise->steps, 2400u);
}

// Where the scans err too, their error enters every step (Eq. 1): the measure is an upper bound
// on the odometry's noise and grows with the scans' error.
TEST(OdometryNoise, IsAnUpperBoundWhereTheScansErrToo) {
  const auto every_other = [](std::size_t k) { return k % 2 == 1; };
  const Drive clean = drive(2001, 0.01, 0.002, 0.99, SE2(), 3, every_other);
  const Drive noisy = drive(2001, 0.01, 0.002, 0.99, SE2(0.02, 0.0, 0.004), 3, every_other);
  const auto a = measureOdometryNoise(clean.scans_alone, clean.priors);
  const auto b = measureOdometryNoise(noisy.scans_alone, noisy.priors);
  ASSERT_TRUE(a && b);
  EXPECT_NEAR(a->sigma_rad, 0.002, 0.15 * 0.002);
  EXPECT_GT(b->sigma_rad, 1.5 * a->sigma_rad);
  EXPECT_GT(b->sigma_m, 1.2 * a->sigma_m);
}

// Too few steps measure nothing (the given noise is kept); fallbacks and steps without an
// odometry step do not count; a perfect odometry gives the floor, never 0 (0 is "no fusion").
TEST(OdometryNoise, NeedsEnoughStepsAndIsNeverZero) {
  Drive d = drive(kMinOdometryNoiseSteps, 0.0, 0.0, 0.99, SE2(), 1);  // one step short
  EXPECT_FALSE(measureOdometryNoise(d.scans_alone, d.priors));
  d = drive(200, 0.0, 0.0, 0.99, SE2(), 1);
  for (std::size_t k = 1; k < 200; ++k)
    if (k % 10 != 0) d.scans_alone.scans[k].fallback = true;  // 19 accepted
  EXPECT_FALSE(measureOdometryNoise(d.scans_alone, d.priors));
  d = drive(200, 0.0, 0.0, 0.99, SE2(), 1);
  for (std::size_t k = 1; k < 200; ++k)
    if (k % 10 != 0) d.priors[k].odometry.reset();  // 19 with an odometry step
  EXPECT_FALSE(measureOdometryNoise(d.scans_alone, d.priors));
  d = drive(200, 0.0, 0.0, 0.99, SE2(), 1);
  const auto noise = measureOdometryNoise(d.scans_alone, d.priors);
  ASSERT_TRUE(noise);
  EXPECT_DOUBLE_EQ(noise->sigma_m, kMinOdometrySigmaM);
  EXPECT_DOUBLE_EQ(noise->sigma_rad, kMinOdometrySigmaRad);
}

}  // namespace
}  // namespace slamprep::algo
