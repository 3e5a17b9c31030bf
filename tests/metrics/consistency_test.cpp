// Consistency statistics (bias, spread, coverage, NEES) against hand-computed values, and their
// power: a sigma three times too small must fail the seeds suite's goals on a small set.
#include "slamprep/eval/metrics/consistency.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <random>

namespace slamprep::eval {
namespace {

TEST(Consistency, StatisticsByHand) {
  // errors 1, -2, 0.5, 3 with sigma 1: within 1 sigma: 1 and 0.5; within 3: all (3 <= 3).
  const ErrorConsistency s = errorConsistency({1.0, -2.0, 0.5, 3.0}, {1.0, 1.0, 1.0, 1.0});
  EXPECT_EQ(s.n, 4);
  EXPECT_DOUBLE_EQ(s.bias, 0.625);                    // 2.5 / 4
  EXPECT_DOUBLE_EQ(s.rms, std::sqrt(14.25 / 4));      // (1 + 4 + 0.25 + 9) / 4
  EXPECT_NEAR(s.std, std::sqrt(12.6875 / 3), 1e-15);  // deviations from 0.625, n - 1
  EXPECT_DOUBLE_EQ(s.coverage_1sigma, 0.5);
  EXPECT_DOUBLE_EQ(s.coverage_3sigma, 1.0);
}

TEST(Consistency, CoverageUsesEachRunsOwnSigma) {
  // |e| / sigma = 0.5, 2, 4: one inside 1 sigma, two inside 3 sigma.
  const ErrorConsistency s = errorConsistency({-1.0, 4.0, 0.4}, {2.0, 2.0, 0.1});
  EXPECT_DOUBLE_EQ(s.coverage_1sigma, 1.0 / 3);
  EXPECT_DOUBLE_EQ(s.coverage_3sigma, 2.0 / 3);
  // mean 17/15; deviations -32/15, 43/15, -11/15: (1024 + 1849 + 121) / 225 / 2.
  EXPECT_NEAR(s.std, std::sqrt(2994.0 / 450.0), 1e-14);
}

TEST(Consistency, NeesWithAKnownCovariance) {
  // P = [[4, 2], [2, 3]], P^-1 = [[3, -2], [-2, 4]] / 8; e = (1, 2): (3 - 8 + 16) / 8 = 1.375.
  Eigen::Matrix2d P;
  P << 4, 2, 2, 3;
  EXPECT_NEAR(*normalizedErrorSquared(Eigen::Vector2d(1, 2), P), 1.375, 1e-14);
  // Mixed units many decades apart (m^2 beside rad^2): 1 + 1.
  const Eigen::Vector2d var(1e-12, 1e-6);
  EXPECT_NEAR(
      *normalizedErrorSquared(Eigen::Vector2d(1e-6, -1e-3), var.asDiagonal().toDenseMatrix()), 2.0,
      1e-12);
}

TEST(Consistency, NeesRefusesASingularOrMismatchedCovariance) {
  Eigen::Matrix2d singular;
  singular << 1, 1, 1, 1;
  EXPECT_FALSE(normalizedErrorSquared(Eigen::Vector2d(1, 0), singular));
  EXPECT_FALSE(normalizedErrorSquared(Eigen::Vector3d(1, 0, 0), Eigen::Matrix2d::Identity()));
  EXPECT_FALSE(normalizedErrorSquared(Eigen::Vector2d(1, 0), -Eigen::Matrix2d::Identity()));
}

// The seeds suite's goals on 6 correlated parameters: coverage_1sigma in [0.55, 0.80],
// coverage_3sigma >= 0.95 for each, mean NEES in [5, 7].
bool meetsGoals(const std::vector<Eigen::VectorXd>& errors, const Eigen::MatrixXd& P) {
  double nees = 0.0;
  for (const auto& e : errors) nees += *normalizedErrorSquared(e, P) / errors.size();
  bool ok = nees >= 5.0 && nees <= 7.0;
  for (Eigen::Index i = 0; i < P.rows(); ++i) {
    std::vector<double> e, s;
    for (const auto& v : errors) {
      e.push_back(v(i));
      s.push_back(std::sqrt(P(i, i)));
    }
    const ErrorConsistency c = errorConsistency(e, s);
    ok = ok && c.coverage_1sigma >= 0.55 && c.coverage_1sigma <= 0.80 && c.coverage_3sigma >= 0.95;
  }
  return ok;
}

TEST(Consistency, ASigmaThreeTimesTooSmallFailsTheGoalsOnASmallSet) {
  // 100 draws from N(0, P), P correlated with standard deviations 1e-4 to 1 (the calibration's
  // mixed units). With the true P the goals hold (their bands are ~3 binomial standard errors
  // wide at n = 100); reporting P / 9 (sigma / 3) puts ~26 % inside 1 sigma and NEES near 54.
  Eigen::MatrixXd A = Eigen::MatrixXd::Identity(6, 6);
  A(1, 0) = 0.8;
  A(5, 3) = -0.5;
  const Eigen::VectorXd scale = (Eigen::VectorXd(6) << 1e-4, 1e-4, 1e-3, 1e-3, 1e-2, 1).finished();
  const Eigen::MatrixXd L = scale.asDiagonal() * A;
  const Eigen::MatrixXd P = L * L.transpose();
  std::mt19937_64 rng(7);
  std::normal_distribution<double> gauss;
  std::vector<Eigen::VectorXd> errors;
  for (int t = 0; t < 100; ++t) {
    Eigen::VectorXd z(6);
    for (int i = 0; i < 6; ++i) z(i) = gauss(rng);
    errors.push_back(L * z);
  }
  EXPECT_TRUE(meetsGoals(errors, P));
  EXPECT_FALSE(meetsGoals(errors, P / 9.0));
  double nees_small = 0.0;
  for (const auto& e : errors) nees_small += *normalizedErrorSquared(e, P / 9.0) / errors.size();
  EXPECT_GT(nees_small, 30.0);
}

}  // namespace
}  // namespace slamprep::eval
