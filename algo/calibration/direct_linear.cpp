#include "slamprep/algo/calibration/direct_linear.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace slamprep::algo {

DiffDriveParams geometryFromTwistMap(const Eigen::Matrix2d& K, const DiffDriveParams& nominal) {
  const Eigen::Matrix2d J = K * nominal.jacobian();  // J = [[r_L/2, r_R/2], [-r_L/b, r_R/b]]
  const double r_L = 2.0 * J(0, 0), r_R = 2.0 * J(0, 1);
  // 1/b minimising (-r_L/b - J21)^2 + (r_R/b - J22)^2.
  const double inv_b = (-r_L * J(1, 0) + r_R * J(1, 1)) / (r_L * r_L + r_R * r_R);
  return {r_L, r_R, inv_b != 0.0 ? 1.0 / inv_b : 0.0};
}

namespace {

/// The stacked problem U X^T = U*: row i of U is interval i's nominal odometry increment u_i^T,
/// row i of U* its lidar motion u*_i^T.
struct DirectLinearSystem {
  Eigen::MatrixXd U, Ustar;
};

DirectLinearSystem stackIntervals(const std::vector<CalibrationInterval>& intervals,
                                  const DiffDriveParams& nominal) {
  const auto n = static_cast<Eigen::Index>(intervals.size());
  DirectLinearSystem sys{Eigen::MatrixXd(n, 3), Eigen::MatrixXd(n, 3)};
  for (Eigen::Index i = 0; i < n; ++i) {
    sys.U.row(i) = integrateInterval(intervals[i], nominal).vector().transpose();
    sys.Ustar.row(i) = intervals[i].T_lidarStart_lidarEnd.vector().transpose();
  }
  return sys;
}

std::string illConditionedReason(double condition_number,
                                 const std::vector<CalibrationInterval>& intervals) {
  return "odometry increments do not span x, y and theta (condition number " +
         (std::isfinite(condition_number) ? std::to_string(condition_number) : std::string("inf")) +
         "): " + describeDegenerateDriving(intervals);
}

/// Solves the three rows of X (independent 3-unknown problems sharing U) and fills X, its
/// 1-sigmas and the cost; returns each row's residual variance.
Eigen::Vector3d solveRowsOfX(const DirectLinearSystem& sys, const Eigen::Matrix3d& UtU_inv,
                             DirectLinearResult& result) {
  const double dof = static_cast<double>(sys.U.rows() - 3);
  const Eigen::Matrix3d Xt = sys.U.colPivHouseholderQr().solve(sys.Ustar);
  result.X = Xt.transpose();
  Eigen::Vector3d var_row;
  for (int r = 0; r < 3; ++r) {
    var_row(r) = (sys.Ustar.col(r) - sys.U * Xt.col(r)).squaredNorm() / dof;
    result.X_sigma.row(r) = (var_row(r) * UtU_inv.diagonal()).cwiseSqrt().transpose();
    result.cost += var_row(r) * dof;
  }
  return var_row;
}

std::string negativeGeometryReason(const DiffDriveParams& g) {
  return "X implies a negative radius or wheel base (r_L = " + std::to_string(g.radius_left_m) +
         ", r_R = " + std::to_string(g.radius_right_m) + ", b = " + std::to_string(g.wheel_base_m) +
         "): left/right swapped or an encoder counting backwards";
}

/// Covariance of (X11, X13, X31, X33) = (K11, K12, K21, K22): rows are independent problems.
Eigen::Matrix4d twistMapCovariance(const Eigen::Vector3d& var_row, const Eigen::Matrix3d& UtU_inv) {
  Eigen::Matrix4d cov_k = Eigen::Matrix4d::Zero();
  const int idx[2] = {0, 2};
  for (int a = 0; a < 2; ++a)
    for (int c = 0; c < 2; ++c) {
      cov_k(a, c) = var_row(0) * UtU_inv(idx[a], idx[c]);
      cov_k(2 + a, 2 + c) = var_row(2) * UtU_inv(idx[a], idx[c]);
    }
  return cov_k;
}

/// Jacobian of the implied geometry w.r.t. (K11, K12, K21, K22), central differences.
Eigen::Matrix<double, 3, 4> geometryJacobianInK(const Eigen::Matrix2d& K,
                                                const DiffDriveParams& nominal) {
  Eigen::Matrix<double, 3, 4> D;
  for (int j = 0; j < 4; ++j) {
    const double h = 1e-7 * std::max(1.0, std::abs(K(j / 2, j % 2)));
    Eigen::Matrix2d Kp = K, Km = K;
    Kp(j / 2, j % 2) += h;
    Km(j / 2, j % 2) -= h;
    const DiffDriveParams gp = geometryFromTwistMap(Kp, nominal);
    const DiffDriveParams gm = geometryFromTwistMap(Km, nominal);
    D.col(j) =
        Eigen::Vector3d(gp.radius_left_m - gm.radius_left_m, gp.radius_right_m - gm.radius_right_m,
                        gp.wheel_base_m - gm.wheel_base_m) /
        (2 * h);
  }
  return D;
}

}  // namespace

DirectLinearResult calibrateDirectLinear(const std::vector<CalibrationInterval>& intervals,
                                         const DirectLinearParams& params) {
  DirectLinearResult result;
  const auto n = static_cast<Eigen::Index>(intervals.size());
  const int min_n = std::max(params.min_intervals, kMinIntervalsAbsolute + 1);
  if (n < min_n) {
    result.reason = "too few intervals: " + std::to_string(n) + " (need at least " +
                    std::to_string(min_n) + ")";
    return result;
  }
  // Each interval gives three equations; they separate into one 3-unknown problem per row of X
  // sharing the design U (rows u_i^T): U X^T = U*.
  const DirectLinearSystem sys = stackIntervals(intervals, params.nominal);
  result.condition_number = equilibratedConditionNumber(sys.U);
  if (!(result.condition_number <= params.max_condition_number)) {
    result.reason = illConditionedReason(result.condition_number, intervals);
    return result;
  }
  const Eigen::Matrix3d UtU_inv = (sys.U.transpose() * sys.U).inverse();
  const Eigen::Vector3d var_row = solveRowsOfX(sys, UtU_inv, result);
  result.K << result.X(0, 0), result.X(0, 2), result.X(2, 0), result.X(2, 2);
  result.geometry = geometryFromTwistMap(result.K, params.nominal);
  const DiffDriveParams& g = result.geometry;
  if (!(g.radius_left_m > 0.0 && g.radius_right_m > 0.0 && g.wheel_base_m > 0.0)) {
    result.reason = negativeGeometryReason(g);
    return result;
  }
  const Eigen::Matrix<double, 3, 4> D = geometryJacobianInK(result.K, params.nominal);
  result.covariance = D * twistMapCovariance(var_row, UtU_inv) * D.transpose();
  result.intervals_used = static_cast<int>(n);
  result.iterations = 1;
  result.ok = true;
  return result;
}

}  // namespace slamprep::algo
