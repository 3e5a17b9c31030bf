#include "slamprep/algo/calibration/mount_prior.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <numbers>

namespace slamprep::algo {

std::optional<MountPriorUse> applyMountPrior(CalibrationResult& result, const MountPrior& prior) {
  if (!result.ok || !result.estimates_mount || result.covariance.rows() != 6 ||
      result.covariance.cols() != 6)
    return std::nullopt;
  const Eigen::VectorXd x = calibrationValues(result);
  const Eigen::MatrixXd& P = result.covariance;
  const SE2& z = prior.T_base_lidar;
  const Eigen::Vector3d nu(z.x - x(3), z.y - x(4),
                           std::remainder(z.yaw - x(5), 2.0 * std::numbers::pi));
  const Eigen::Vector3d r_diag(prior.sigma_xy_m * prior.sigma_xy_m,
                               prior.sigma_xy_m * prior.sigma_xy_m,
                               prior.sigma_yaw_rad * prior.sigma_yaw_rad);
  const Eigen::Matrix3d S = P.bottomRightCorner<3, 3>() + Eigen::Matrix3d(r_diag.asDiagonal());
  const Eigen::LDLT<Eigen::Matrix3d> S_inv(S);
  MountPriorUse use{prior, nu.dot(S_inv.solve(nu)), false, x, result.sigma()};
  if (!(use.chi2 <= prior.max_chi2)) return use;  // Eq. (2): the fit contradicts the prior
  const Eigen::MatrixXd PHt = P.rightCols<3>();   // P H^T
  const Eigen::MatrixXd K = S_inv.solve(PHt.transpose()).transpose();  // Eq. (3)
  const Eigen::VectorXd fused = x + K * nu;
  Eigen::MatrixXd I_KH = Eigen::MatrixXd::Identity(6, 6);
  I_KH.rightCols<3>() -= K;
  result.covariance = I_KH * P * I_KH.transpose() + K * r_diag.asDiagonal() * K.transpose();
  result.geometry = {fused(0), fused(1), fused(2)};
  result.T_base_lidar = SE2(fused(3), fused(4), fused(5));
  use.applied = true;
  return use;
}

}  // namespace slamprep::algo
