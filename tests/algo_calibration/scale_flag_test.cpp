// Wheels and wheel base off the nominal by one factor (algo/calibration/scale_flag.hpp): what a
// lidar reading its ranges long or short gives, flagged with that cause; the common factor
// against brute force.
#include "slamprep/algo/calibration/scale_flag.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace slamprep::algo {
namespace {

const DiffDriveParams kNominal{0.035, 0.035, 0.24};

/// A result at the nominal geometry scaled by (left, right, base), with sigmas of 0.2 % of r and
/// b and the radii correlated with b as calibrations make them (rho 0.8).
CalibrationResult scaled(double left, double right, double base) {
  CalibrationResult r;
  r.ok = true;
  r.geometry = {left * kNominal.radius_left_m, right * kNominal.radius_right_m,
                base * kNominal.wheel_base_m};
  const Eigen::Vector3d sigma =
      0.002 *
      Eigen::Vector3d(kNominal.radius_left_m, kNominal.radius_right_m, kNominal.wheel_base_m);
  Eigen::Matrix3d rho;
  rho << 1.0, 0.8, 0.8, 0.8, 1.0, 0.8, 0.8, 0.8, 1.0;
  r.covariance = sigma.asDiagonal() * rho * sigma.asDiagonal();
  return r;
}

// A lidar reading 1.4 % long (the Freiburg hospital's): r_L, r_R and b 1.4 % large together.
TEST(ScaleFlag, OneFactorOnWheelsAndBaseIsFlaggedWithTheRangeScale) {
  const auto flag = scaleFlag(scaled(1.014, 1.014, 1.014), kNominal);
  ASSERT_TRUE(flag);
  EXPECT_EQ(flag->param, "range_scale");
  EXPECT_NEAR(flag->ratio, 1.014, 1e-12);
  EXPECT_NE(flag->likely_cause.find("1.40 % above"), std::string::npos) << flag->likely_cause;
  EXPECT_NE(flag->likely_cause.find("read 1.40 % long"), std::string::npos);
  const auto shorter = scaleFlag(scaled(0.98, 0.98, 0.98), kNominal);
  ASSERT_TRUE(shorter);
  EXPECT_NE(shorter->likely_cause.find("short"), std::string::npos);
}

TEST(ScaleFlag, RadiiOffWithoutTheBaseOrWithinTheSigmaAreNot) {
  EXPECT_FALSE(scaleFlag(scaled(1.014, 1.014, 1.0), kNominal));    // radii alone: not a range scale
  EXPECT_FALSE(scaleFlag(scaled(1.02, 0.985, 1.04), kNominal));    // the simulator's wrong nominal
  EXPECT_FALSE(scaleFlag(scaled(1.003, 1.003, 1.003), kNominal));  // 1.6 sigma of the factor
  CalibrationResult refused = scaled(1.014, 1.014, 1.014);
  refused.ok = false;
  EXPECT_FALSE(scaleFlag(refused, kNominal));
}

// Eq. 1-2 against brute force: the factor minimises the generalised chi2 over a fine grid.
TEST(ScaleFlag, TheCommonFactorMinimisesTheChi2) {
  const CalibrationResult r = scaled(1.012, 1.008, 1.016);
  const std::optional<CommonScale> s = commonScale(r, kNominal);
  ASSERT_TRUE(s);
  const Eigen::Vector3d n(kNominal.radius_left_m, kNominal.radius_right_m, kNominal.wheel_base_m);
  const Eigen::Vector3d q = calibrationValues(r).head<3>().cwiseQuotient(n);
  const Eigen::Matrix3d C_inverse =
      (n.cwiseInverse().asDiagonal() * r.covariance * n.cwiseInverse().asDiagonal()).inverse();
  double best = 0.0, best_chi2 = std::numeric_limits<double>::infinity();
  for (double f = 0.99; f < 1.03; f += 1e-6) {
    const Eigen::Vector3d d = q - f * Eigen::Vector3d::Ones();
    if (const double chi2 = d.dot(C_inverse * d); chi2 < best_chi2) best_chi2 = chi2, best = f;
  }
  EXPECT_NEAR(s->factor, best, 2e-6);
  EXPECT_NEAR(s->chi2, best_chi2, 1e-6 * best_chi2);
  // sigma: where the chi2 of the factor alone rises by 1.
  const double information = Eigen::Vector3d::Ones().dot(C_inverse * Eigen::Vector3d::Ones());
  EXPECT_NEAR(s->sigma, 1.0 / std::sqrt(information), 1e-15);
}

}  // namespace
}  // namespace slamprep::algo
