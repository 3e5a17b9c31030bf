#include <gtest/gtest.h>

#include "slamprep/eval/bench/trial.hpp"

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

// The split of the de-skew error by cause (docs/metrics.md) as bench reports it.
TEST(BenchTrial, SplitsDeskewErrorIntoRotationAndTranslation) {
  const Suite suite = circleSuite();
  const TrialOutput out = benchTrial(suite)(expandTrials(suite).front());
  for (const char* method : {"none", "oracle", "odom-linear"}) {
    const auto& d = out.result["deskew"][method];
    SCOPED_TRACE(method);
    // The true points use the measured ranges, so the two parts explain the error exactly.
    EXPECT_LT(d["split_residual_max_m"].get<double>(), 1e-9);
    // |e| <= |rot| + |trans| beam by beam, hence for the means as well.
    EXPECT_LE(d["mean_m"].get<double>(),
              d["rotation_mean_m"].get<double>() + d["translation_mean_m"].get<double>() + 1e-12);
  }
  EXPECT_LT(out.result["deskew"]["oracle"]["rotation_mean_m"].get<double>(), 1e-6);
  EXPECT_LT(out.result["deskew"]["oracle"]["translation_mean_m"].get<double>(), 1e-6);
  // Nominal odometry is wrong mostly in yaw rate (10.3 %, see above: ~15 mm at 3 m over half a
  // scan) and little in speed (~0.3 %) or the mount lever (0.1 rad/s * 0.1 m): rotation dominates.
  const auto& odom = out.result["deskew"]["odom-linear"];
  EXPECT_GT(odom["rotation_mean_m"].get<double>(), 10 * odom["translation_mean_m"].get<double>());
  // Without correction the translation part is the lidar's own travel since the first beam:
  // 0.985 m/s (base 1 m/s plus w x mount lever) over at most one 0.1 s scan.
  const auto& none = out.result["deskew"]["none"];
  EXPECT_GT(none["translation_mean_m"].get<double>(), 0.01);
  EXPECT_LT(none["translation_mean_m"].get<double>(), 0.0985 / 2 + 1e-3);
}

// Dead-reckoning errors with evo's definitions, for the nominal and the true geometry.
TEST(BenchTrial, ReportsOdometryApeAndRpe) {
  Suite suite = circleSuite();
  suite.duration_s = 4.0;  // ~3.5 m of path: RPE needs two whole 1 m stretches after the first
  const TrialOutput out = benchTrial(suite)(expandTrials(suite).front());
  const auto& nominal = out.result["odometry"]["nominal"];
  const auto& truth = out.result["odometry"]["true"];
  // Kinematic mode: the true geometry reproduces the truth up to encoder quantisation (0.15 mm of
  // wheel travel per tick, not accumulating: ticks are cumulative).
  EXPECT_LT(truth["ape_max_m"].get<double>(), 1e-3);
  EXPECT_LT(truth["rpe_rot_rmse_deg"].get<double>(), 0.05);
  // Nominal: the controller commands (1 m/s, 1 rad/s) through the nominal geometry, so the true
  // wheels turn at (0.74 / 0.102, 1.26 / 0.0985) = (7.25, 12.79) rad/s: truly v = 1.002 m/s,
  // w = 1.107 rad/s, while the odometry believes exactly (1, 1). Per metre of odometry path the
  // robot turns 1.107 / 1.0 rad against a believed 1 rad: 0.107 rad = 6.1 deg (ramps aside).
  EXPECT_NEAR(nominal["rpe_rot_rmse_deg"].get<double>(), 6.1, 0.5);
  EXPECT_GT(nominal["ape_max_m"].get<double>(), 0.05);
  EXPECT_LE(nominal["ape_rmse_m"].get<double>(), nominal["ape_max_m"].get<double>());
}

TEST(BenchTrial, SameSpecSameResult) {
  const Suite suite = circleSuite();
  const auto spec = expandTrials(suite).front();
  EXPECT_EQ(benchTrial(suite)(spec).result.dump(), benchTrial(suite)(spec).result.dump());
}

}  // namespace
}  // namespace slamprep::eval
