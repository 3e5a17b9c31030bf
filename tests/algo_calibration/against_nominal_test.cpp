// The estimate against the nominal geometry (algo/calibration/against_nominal.hpp): the chi2's
// tail against brute-force integration, its false-alarm rate over draws about the nominal, and
// the simulator's wrong nominal told apart from noise.
#include "slamprep/algo/calibration/against_nominal.hpp"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <cmath>
#include <numbers>
#include <random>

namespace slamprep::algo {
namespace {

const DiffDriveParams kNeatoNominal{0.036, 0.036, 0.248};

/// A result at the nominal geometry times (left, right, base), sigmas `relative` of each value,
/// every pair correlated by rho (calibrations correlate r with b: r / b is what turns pin down).
CalibrationResult neatoScaled(double left, double right, double base, double relative,
                              double rho = 0.8) {
  CalibrationResult r;
  r.ok = true;
  r.geometry = {left * kNeatoNominal.radius_left_m, right * kNeatoNominal.radius_right_m,
                base * kNeatoNominal.wheel_base_m};
  const Eigen::Vector3d sigma =
      relative * Eigen::Vector3d(kNeatoNominal.radius_left_m, kNeatoNominal.radius_right_m,
                                 kNeatoNominal.wheel_base_m);
  Eigen::Matrix3d correlation = Eigen::Matrix3d::Constant(rho);
  correlation.diagonal().setOnes();
  r.covariance = sigma.asDiagonal() * correlation * sigma.asDiagonal();
  return r;
}

// Eq. 2 against the density of chi2 with 3 degrees of freedom, sqrt(x) exp(-x/2) / sqrt(2 pi),
// integrated by Simpson's rule from x to 200; and the table's quantiles.
TEST(AgainstNominal, TheTailIsTheIntegralOfTheChi2Density) {
  const auto density = [](double x) {
    return std::sqrt(x) * std::exp(-0.5 * x) / std::sqrt(2.0 * std::numbers::pi);
  };
  for (const double x : {0.1, 1.0, 3.0, 7.8147, 16.27, 30.0}) {
    const int n = 200000;
    const double h = (200.0 - x) / n;
    double sum = density(x) + density(200.0);
    for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * density(x + i * h);
    EXPECT_NEAR(chi2Survival3(x), sum * h / 3.0, 1e-9) << x;
  }
  EXPECT_NEAR(chi2Survival3(7.8147), 0.05, 1e-5);
  EXPECT_NEAR(chi2Survival3(11.3449), 0.01, 1e-5);
  EXPECT_NEAR(chi2Survival3(16.2662), 0.001, 1e-6);
  EXPECT_EQ(chi2Survival3(0.0), 1.0);
}

// Eq. 1 with the covariance's inverse written out, and the correlation's part in it: radii
// moved apart by one sigma each are far less likely than either alone says, as r_L - r_R is
// pinned down by straight driving.
TEST(AgainstNominal, Chi2UsesTheCorrelation) {
  const CalibrationResult r = neatoScaled(1.02, 0.98, 1.0, 0.02);
  const std::optional<NominalTest> t = nominalTest(r, kNeatoNominal);
  ASSERT_TRUE(t);
  const Eigen::Vector3d d = calibrationValues(r) - Eigen::Vector3d(0.036, 0.036, 0.248);
  EXPECT_NEAR(t->chi2, d.dot(r.covariance.inverse() * d), 1e-9);
  EXPECT_NEAR(t->z(0), 1.0, 1e-9);
  EXPECT_NEAR(t->z(1), -1.0, 1e-9);
  EXPECT_NEAR(t->z(2), 0.0, 1e-9);
  EXPECT_GT(t->chi2, 5.0 * t->z.squaredNorm());  // 2 / (2 (1 - 0.8)) per unit, and b's pull
}

// Estimates drawn about the nominal with their own covariance: the test says "wrong" as often
// as its level says (10000 draws: binomial sd 0.22 % at 5 %, 0.03 % at 0.1 %).
TEST(AgainstNominal, FalseAlarmsAtTheRateOfItsLevel) {
  const CalibrationResult base = neatoScaled(1.0, 1.0, 1.0, 0.01);
  const Eigen::Matrix3d L = base.covariance.llt().matrixL();
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  int at_5 = 0, wrong = 0;
  const int n = 10000;
  for (int i = 0; i < n; ++i) {
    CalibrationResult r = base;
    const Eigen::Vector3d e = L * Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
    r.geometry = {kNeatoNominal.radius_left_m + e(0), kNeatoNominal.radius_right_m + e(1),
                  kNeatoNominal.wheel_base_m + e(2)};
    const std::optional<NominalTest> t = nominalTest(r, kNeatoNominal);
    ASSERT_TRUE(t);
    at_5 += t->p < 0.05;
    wrong += t->shows_nominal_wrong;
  }
  EXPECT_NEAR(double(at_5) / n, 0.05, 4 * 0.0022);
  EXPECT_NEAR(double(wrong) / n, 0.001, 4 * 0.00032);
}

// The simulator's wrong nominal (r_L +2 %, r_R -1.5 %, b +4 %): shown wrong by a calibration
// with 0.5 % sigmas, not by one with 5 % (a short real recording's).
TEST(AgainstNominal, AWrongNominalIsShownWhereTheSigmasAreSmallerThanItsError) {
  const std::optional<NominalTest> sharp =
      nominalTest(neatoScaled(1.02, 0.985, 1.04, 0.005), kNeatoNominal);
  ASSERT_TRUE(sharp);
  EXPECT_TRUE(sharp->shows_nominal_wrong);
  EXPECT_LT(sharp->p, 1e-6);
  const std::optional<NominalTest> loose =
      nominalTest(neatoScaled(1.02, 0.985, 1.04, 0.05), kNeatoNominal);
  ASSERT_TRUE(loose);
  EXPECT_FALSE(loose->shows_nominal_wrong);
  EXPECT_GT(loose->p, 0.01);
}

TEST(AgainstNominal, NoTestOfARefusedResultOrASingularCovariance) {
  CalibrationResult refused = neatoScaled(1.02, 0.985, 1.04, 0.005);
  refused.ok = false;
  EXPECT_FALSE(nominalTest(refused, kNeatoNominal));
  EXPECT_FALSE(nominalTest(neatoScaled(1.02, 0.985, 1.04, 0.005, 1.0), kNeatoNominal));  // rank 1
  CalibrationResult none = neatoScaled(1.0, 1.0, 1.0, 0.005);
  none.covariance.resize(0, 0);
  EXPECT_FALSE(nominalTest(none, kNeatoNominal));
}

}  // namespace
}  // namespace slamprep::algo
