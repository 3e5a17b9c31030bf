// The recording's mount as a prior on joint's and ceres' mount (algo/calibration/mount_prior.hpp):
// the update against the brute-force minimiser of its two quadratic terms, the wheels moved by
// their correlation with the mount, and a fit that contradicts the prior left alone.
#include "slamprep/algo/calibration/mount_prior.hpp"

#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <numbers>

namespace slamprep::algo {
namespace {

constexpr double kPriorTestDeg = std::numbers::pi / 180.0;

// A joint fit with a loose mount whose x is correlated with b (as in a drive with little
// turning): covariance A A^T + small diagonal from a fixed A.
CalibrationResult looseFit() {
  CalibrationResult r;
  r.ok = true;
  r.estimates_mount = true;
  r.geometry = {0.034, 0.035, 0.26};
  r.T_base_lidar = SE2(-0.02, 0.05, 178.0 * kPriorTestDeg);
  Eigen::Matrix<double, 6, 6> A;
  A << 1e-3, 0, 2e-3, 0, 0, 0,   //
      0, 1e-3, 2e-3, 0, 0, 0,    //
      0, 0, 1.5e-2, 4e-2, 0, 0,  //
      0, 0, 0, 6e-2, 1e-2, 0,    //
      0, 0, 0, 0, 5e-2, 0,       //
      0, 0, 0, 0, 0, 3e-2;
  r.covariance = A * A.transpose() + Eigen::MatrixXd::Identity(6, 6) * 1e-10;
  return r;
}

MountPrior tf() {
  return {SE2(-0.1, 0.0, 180.0 * kPriorTestDeg), "tf base_link -> laser"};
}

// The minimiser of (x - x0)^T P^-1 (x - x0) + (H x - z)^T R^-1 (H x - z) from its normal
// equations, and its inverse Hessian: what Eq. (3) must equal.
TEST(MountPrior, EqualsTheMinimiserOfFitAndPriorTogether) {
  CalibrationResult r = looseFit();
  const Eigen::VectorXd x0 = calibrationValues(r);
  const Eigen::MatrixXd P = r.covariance;
  const MountPrior prior = tf();
  const auto use = applyMountPrior(r, prior);
  ASSERT_TRUE(use && use->applied) << (use ? use->chi2 : -1);

  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(3, 6);
  H.rightCols<3>().setIdentity();
  const Eigen::Vector3d r_inv(1.0 / (prior.sigma_xy_m * prior.sigma_xy_m),
                              1.0 / (prior.sigma_xy_m * prior.sigma_xy_m),
                              1.0 / (prior.sigma_yaw_rad * prior.sigma_yaw_rad));
  // z with its yaw unwrapped next to the fit's (178 deg against 180 deg: 2 deg apart).
  const Eigen::Vector3d z(prior.T_base_lidar.x, prior.T_base_lidar.y, 180.0 * kPriorTestDeg);
  const Eigen::MatrixXd P_inv = P.inverse();
  const Eigen::MatrixXd hessian = P_inv + H.transpose() * r_inv.asDiagonal() * H;
  const Eigen::VectorXd x =
      hessian.ldlt().solve(P_inv * x0 + H.transpose() * r_inv.asDiagonal() * z);
  const Eigen::VectorXd fused = calibrationValues(r);
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(fused(i), x(i), 1e-9) << i;
  EXPECT_NEAR(std::remainder(fused(5) - x(5), 2 * std::numbers::pi), 0.0, 1e-9);
  EXPECT_LT((r.covariance - hessian.inverse()).cwiseAbs().maxCoeff(), 1e-12);
  // The wheels moved through their correlation with the mount: b with lidar x.
  EXPECT_GT(std::abs(fused(2) - x0(2)), 1e-3);
  // What the fit said alone is kept for the JSON.
  EXPECT_EQ(use->without_prior, x0);
  EXPECT_NEAR(use->without_prior_sigma(3), std::sqrt(P(3, 3)), 1e-15);
}

TEST(MountPrior, AFitThatContradictsThePriorIsLeftAlone) {
  CalibrationResult r = looseFit();
  r.covariance.bottomRightCorner<3, 3>() = Eigen::Matrix3d::Identity() * 1e-6;  // 1 mm, 0.06 deg
  r.covariance.topRightCorner<3, 3>().setZero();
  r.covariance.bottomLeftCorner<3, 3>().setZero();
  const CalibrationResult before = r;
  const auto use = applyMountPrior(r, tf());
  ASSERT_TRUE(use);
  EXPECT_FALSE(use->applied);
  // (8 cm, 5 cm, 2 deg) against sigmas of 2 cm and 2 deg: chi2 near 16 + 6.25 + 1.
  EXPECT_GT(use->chi2, 14.16);
  EXPECT_EQ(calibrationValues(r), calibrationValues(before));
  EXPECT_EQ(r.covariance, before.covariance);
}

TEST(MountPrior, OnlyForAnOkFitThatEstimatesTheMount) {
  CalibrationResult r = looseFit();
  r.ok = false;
  EXPECT_FALSE(applyMountPrior(r, tf()));
  r = looseFit();
  r.estimates_mount = false;
  r.covariance = Eigen::MatrixXd::Identity(3, 3);
  EXPECT_FALSE(applyMountPrior(r, tf()));
}

}  // namespace
}  // namespace slamprep::algo
