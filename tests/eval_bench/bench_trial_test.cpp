#include <gtest/gtest.h>

#include "eval/bench/trial.hpp"

namespace slamprep::eval {
namespace {

// A short kinematic circle at 1 m/s and 1 rad/s: enough scans to measure de-skew, fast to run.
Suite circleSuite() {
  Suite suite;
  suite.name = "test";
  suite.source = "test.yaml";
  suite.worlds = {"worlds/room.yaml"};
  suite.scenarios = {"worlds/scenarios/arc.yaml"};
  suite.mode = "kinematic";
  suite.duration_s = 2.0;
  suite.deskew_methods = {"none", "oracle", "odom-linear"};
  return suite;
}

TEST(BenchTrial, MeasuresDeskewAgainstTruth) {
  const Suite suite = circleSuite();
  const TrialOutput out = benchTrial(suite)(expandTrials(suite).front());
  const auto& deskew = out.result["deskew"];
  // The oracle uses the same true poses the simulator cast the beams from: only interpolation
  // rounding remains (far below a micrometre).
  EXPECT_LT(deskew["oracle"]["mean_m"].get<double>(), 1e-6);
  // Uncorrected at 1 rad/s over a 0.1 s scan: points rotate by up to 0.1 rad, so errors are
  // centimetres to decimetres at room ranges.
  EXPECT_GT(deskew["none"]["mean_m"].get<double>(), 0.02);
  // Odometry with the nominal geometry (r_L +2 %, r_R -1.5 %, b +4 %) believes the yaw rate is
  // (0.0985 * 12.5 - 0.102 * 7.5) / 0.52 = 0.897 rad/s at wheel rates (7.5, 12.5) rad/s, so it
  // leaves ~10.3 % of the rotational distortion: the ratio to `none` must sit near 0.103.
  const double ratio =
      deskew["odom-linear"]["mean_m"].get<double>() / deskew["none"]["mean_m"].get<double>();
  EXPECT_GT(ratio, 0.07);
  EXPECT_LT(ratio, 0.14);
  EXPECT_EQ(deskew["none"]["beams"].get<std::size_t>(),
            deskew["oracle"]["beams"].get<std::size_t>());
  EXPECT_NEAR(out.result["sim"]["duration_s"].get<double>(), 2.0, 1e-9);
}

TEST(BenchTrial, TrueGeometryMakesOdometryDeskewSubMillimetre) {
  Suite suite = circleSuite();
  suite.deskew_geometry = "true";
  const TrialOutput out = benchTrial(suite)(expandTrials(suite).front());
  // Left: encoder quantisation (2 pi / 4096 rad per tick, 0.15 mm of wheel travel) and linear
  // interpolation of 100 Hz odometry on a 1 rad/s circle (chord error ~ v dt^2 w / 8 = 0.01 mm).
  EXPECT_LT(out.result["deskew"]["odom-linear"]["mean_m"].get<double>(), 1e-3);
}

TEST(BenchTrial, SameSpecSameResult) {
  const Suite suite = circleSuite();
  const auto spec = expandTrials(suite).front();
  EXPECT_EQ(benchTrial(suite)(spec).result.dump(), benchTrial(suite)(spec).result.dump());
}

}  // namespace
}  // namespace slamprep::eval
