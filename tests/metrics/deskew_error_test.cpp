#include "slamprep/eval/metrics/deskew_error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace slamprep::eval {
namespace {

using std::numbers::pi;

TEST(DeskewError, HandComputedSplitOfOneBeam) {
  // True point (1, 0); the de-skew used a beam pose off by Delta = (0.1, 0, 90 deg):
  // corrected = Delta p = (0.1, 1). Rotation part (R - I) p = (-1, 1), |.| = sqrt(2);
  // translation part (0.1, 0); total (-0.9, 1), |.| = sqrt(1.81).
  const SE2 delta(0.1, 0.0, pi / 2);
  const BeamPoints truth = {Eigen::Vector2d(1, 0)};
  const BeamPoints corrected = {delta * Eigen::Vector2d(1, 0)};
  const DeskewErrorResult r = deskewError(corrected, truth, {delta});
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_NEAR(r.error_m.mean, std::sqrt(1.81), 1e-15);
  EXPECT_NEAR(r.rotation_induced_m.mean, std::sqrt(2.0), 1e-15);
  EXPECT_NEAR(r.translation_induced_m.mean, 0.1, 1e-15);
  EXPECT_LT(r.max_split_residual_m, 1e-15);
}

TEST(DeskewError, PureRotationErrorGrowsWithRangeAndTranslationDoesNot) {
  // Delta = small yaw only: |(R - I) p| = 2 r sin(yaw/2), exactly proportional to range.
  const SE2 rot(0.0, 0.0, 0.01), trans(0.02, -0.01, 0.0);
  BeamPoints truth, by_rot, by_trans;
  for (int i = 0; i < 36; ++i) {
    const double a = i * 2 * pi / 36, range = 1.0 + i;
    truth.push_back(range * Eigen::Vector2d(std::cos(a), std::sin(a)));
    by_rot.push_back(rot * *truth.back());
    by_trans.push_back(trans * *truth.back());
  }
  const DeskewErrorResult r = deskewError(by_rot, truth, std::vector<SE2>(36, rot));
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.error_m.max, 2 * 36.0 * std::sin(0.005), 1e-12);
  EXPECT_NEAR(r.error_m.min, 2 * 1.0 * std::sin(0.005), 1e-12);
  EXPECT_EQ(r.translation_induced_m.max, 0.0);
  EXPECT_NEAR(r.rotation_induced_m.mean, r.error_m.mean, 1e-12);
  const DeskewErrorResult t = deskewError(by_trans, truth, std::vector<SE2>(36, trans));
  ASSERT_TRUE(t.ok);
  EXPECT_NEAR(t.error_m.min, std::hypot(0.02, 0.01), 1e-12);
  EXPECT_NEAR(t.error_m.max, std::hypot(0.02, 0.01), 1e-12);
  EXPECT_EQ(t.rotation_induced_m.max, 0.0);
}

TEST(DeskewError, PartsAddUpToTheTotalForRandomPoseErrors) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> u(-1, 1);
  BeamPoints truth, corrected;
  std::vector<SE2> deltas;
  for (int i = 0; i < 200; ++i) {
    truth.push_back(Eigen::Vector2d(10 * u(rng), 10 * u(rng)));
    // Beam poses as a de-skew would have them: Delta from estimated vs true T_ref_beam.
    const SE2 T_true(0.1 * u(rng), 0.1 * u(rng), 0.2 * u(rng));
    const SE2 T_est = T_true * SE2(0.01 * u(rng), 0.01 * u(rng), 0.01 * u(rng));
    const SE2 delta = beamPoseError(T_est, T_true);
    // p_true = T_true p_L, p_corrected = T_est p_L with the same p_L.
    const Eigen::Vector2d p_L = T_true.inverse() * *truth.back();
    corrected.push_back(T_est * p_L);
    deltas.push_back(delta);
  }
  const DeskewErrorResult r = deskewError(corrected, truth, deltas);
  ASSERT_TRUE(r.ok);
  EXPECT_LT(r.max_split_residual_m, 1e-13);  // coordinates ~10 m: a few ulps
  // Triangle inequality per beam carries over to the means.
  EXPECT_LE(r.error_m.mean, r.rotation_induced_m.mean + r.translation_induced_m.mean + 1e-12);
}

TEST(DeskewError, CountsMissingAndExtraBeams) {
  const BeamPoints truth = {Eigen::Vector2d(1, 0), std::nullopt, Eigen::Vector2d(0, 2),
                            std::nullopt};
  const BeamPoints corrected = {Eigen::Vector2d(1, 0.5), Eigen::Vector2d(3, 3), std::nullopt,
                                std::nullopt};
  const DeskewErrorResult r = deskewError(corrected, truth);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.compared, 1u);
  EXPECT_EQ(r.missing, 1u);
  EXPECT_EQ(r.extra, 1u);
  EXPECT_EQ(r.error_m.mean, 0.5);
  EXPECT_FALSE(r.has_split);
}

TEST(DeskewError, RefusesMismatchedSizesAndEmptyScans) {
  const BeamPoints one = {Eigen::Vector2d(1, 0)};
  EXPECT_FALSE(deskewError(one, {}).ok);
  EXPECT_FALSE(deskewError(one, one, {SE2(), SE2()}).ok);
  const DeskewErrorResult r = deskewError({std::nullopt}, {std::nullopt});
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.reason, "no beam has both a corrected and a true point");
}

// Ray by ray: |r - r_true| where both have a range; lost where only the truth has one.
TEST(RepackedError, ComparesRaysAndCountsLostOnes) {
  const double inf = std::numeric_limits<double>::infinity();
  const RepackedErrorResult r = repackedError({2.0, inf, 3.5, 1.0}, {2.25, 4.0, 3.0, inf});
  EXPECT_EQ(r.errors_m, (std::vector<double>{0.25, 0.5}));
  EXPECT_EQ(r.lost, 1u);
  EXPECT_EQ(r.extra, 1u);
  EXPECT_TRUE(repackedError({1.0}, {}).errors_m.empty());  // not the same grid
}

}  // namespace
}  // namespace slamprep::eval
