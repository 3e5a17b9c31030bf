// The twin's smoother of matched poses (eval/bench/trajectory_smoother.hpp): against brute
// force (with no process noise it is the least-squares straight line), forward and inverse (a
// known motion plus a known white error: the error's sigma comes back, the motion is kept).
#include "slamprep/eval/bench/trajectory_smoother.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace slamprep::eval {
namespace {

// With q -> 0 the constant-velocity model is a straight line: the smoother must return the
// least-squares line through the positions (the Rauch-Tung-Striebel pass made exact by hand).
TEST(TrajectorySmoother, WithoutProcessNoiseIsTheLeastSquaresLine) {
  std::vector<double> t, z;
  for (int k = 0; k < 40; ++k) {
    t.push_back(0.1 * k + 0.01 * (k % 3));                          // irregular stamps
    z.push_back(0.5 + 0.3 * t.back() + 0.002 * ((k * 7) % 5 - 2));  // a line, a bounded wiggle
  }
  double st = 0, sz = 0, stt = 0, stz = 0;
  for (std::size_t k = 0; k < t.size(); ++k)
    st += t[k], sz += z[k], stt += t[k] * t[k], stz += t[k] * z[k];
  const double n = double(t.size());
  const double slope = (n * stz - st * sz) / (n * stt - st * st), offset = (sz - slope * st) / n;
  const std::vector<double> s = smoothAxis(t, z, {0.01, 1e-14, 0.0});
  for (std::size_t k = 0; k < t.size(); ++k) EXPECT_NEAR(s[k], offset + slope * t[k], 2e-6) << k;
}

/// A drive at 7.7 scans per second for 90 s: forward with a sway, turning back and forth.
SE2 motion(double t) {
  return SE2(0.25 * t + 0.3 * std::sin(0.4 * t), 1.2 * std::sin(0.15 * t), 0.6 * std::sin(0.3 * t));
}

// A matched trajectory is the motion plus white error (5 mm, 0.3 deg): the fit finds those
// sigmas within 20 %, and the smoothed poses are nearer the motion than the matches were.
TEST(TrajectorySmoother, FindsTheMatchesErrorAndKeepsTheMotion) {
  std::mt19937 rng(7);
  std::normal_distribution<double> xy(0.0, 0.005), yaw(0.0, 0.3 * std::numbers::pi / 180.0);
  PoseSeries matched;
  for (int k = 0; k < 700; ++k) {
    const double t = k / 7.7;
    const SE2 T = motion(t);
    matched.push_back(t, SE2(T.x + xy(rng), T.y + xy(rng), T.yaw + yaw(rng)));
  }
  const SmoothedTrajectory s = smoothTrajectory(matched);
  EXPECT_NEAR(s.x.measurement, 0.005, 0.001);
  EXPECT_NEAR(s.y.measurement, 0.005, 0.001);
  EXPECT_NEAR(s.yaw.measurement, 0.3 * std::numbers::pi / 180.0, 0.06 * std::numbers::pi / 180.0);
  double before = 0.0, after = 0.0;
  for (std::size_t k = 0; k < matched.size(); ++k) {
    const SE2 truth = motion(matched[k].stamp_s);
    before += (matched[k].value.translation() - truth.translation()).squaredNorm();
    after += (s.T_world_base[k].value.translation() - truth.translation()).squaredNorm();
  }
  EXPECT_LT(after, 0.25 * before);  // the error's variance more than quartered
  EXPECT_NEAR(s.rms_shift_m, std::sqrt(2.0) * 0.005, 0.002);  // what was taken off is the error
}

// A noiseless motion is left where it was, and a short trajectory is returned as it is.
TEST(TrajectorySmoother, LeavesAnExactMotionAlone) {
  PoseSeries exact;
  for (int k = 0; k < 300; ++k) exact.push_back(k / 7.7, motion(k / 7.7));
  EXPECT_LT(smoothTrajectory(exact).rms_shift_m, 2e-4);
  PoseSeries short_run;
  for (int k = 0; k < 5; ++k) short_run.push_back(k, SE2(k, 0.01 * (k % 2), 0));
  EXPECT_EQ(smoothTrajectory(short_run).rms_shift_m, 0.0);
}

}  // namespace
}  // namespace slamprep::eval
