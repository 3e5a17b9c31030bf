#include "slamprep/algo/calibration/ceres_refine.hpp"

#include <ceres/ceres.h>

#include <Eigen/Dense>
#include <cmath>

namespace slamprep::algo {
namespace {

// Residual of one interval (Ceres autodiff functor).
//   o     = integrateStepsShifted(steps; r_L, r_R, b, offset)   exact arcs over the encoder
//           steps inside the lidar window [t_s, t_e], shifted to encoder time by -offset
//   pred  = l^-1 * o * l                                        predicted lidar motion
//   r     = W (t_sm - t_pred, angle(th_sm - th_pred)),  W = diag(1/sigma_x, 1/sigma_y, 1/sigma_th)
// The translation error is taken in the lidar frame at the interval's start, where the scan
// matcher's noise lives (and where joint's residuals are): log(pred^-1 * sm) would express it
// in the predicted end frame, rotated by the interval's turn, and mix the per-axis sigmas.
// p = (r_L, r_R, b, l_x, l_y, l_th); offset and the sideslip k separate one-element blocks
// (constant unless estimated). With the sideslip, o = integrateStepsWithSideslip(steps; r_L,
// r_R, b, k): every step also moves the base sideways by k ds dth / dt.
struct IntervalResidual {
  const CalibrationInterval* interval;
  Eigen::Vector3d inv_sigma;
  bool sideslip;

  template <typename T>
  bool operator()(const T* p, const T* offset, const T* k, T* residual) const {
    const SE2T<T> o = sideslip
                          ? integrateStepsWithSideslip(interval->steps, p[0], p[1], p[2], k[0])
                          : integrateStepsShifted(interval->steps, p[0], p[1], p[2], offset[0]);
    const SE2T<T> pred = lidarMotion(o, SE2T<T>(p[3], p[4], p[5]));
    const SE2T<T> sm = interval->T_lidarStart_lidarEnd.template cast<T>();
    residual[0] = (sm.x - pred.x) * inv_sigma(0);
    residual[1] = (sm.y - pred.y) * inv_sigma(1);
    residual[2] = normalizeAngle(sm.yaw - pred.yaw) * inv_sigma(2);
    return true;
  }
};

void buildProblem(const std::vector<CalibrationInterval>& intervals, const Eigen::Vector3d& sigma,
                  const CeresParams& params, double* p, double* offset, double* sideslip,
                  ceres::Problem& problem) {
  const Eigen::Vector3d inv_sigma = sigma.cwiseInverse();
  for (const CalibrationInterval& interval : intervals) {
    auto* cost = new ceres::AutoDiffCostFunction<IntervalResidual, 3, 6, 1, 1>(
        new IntervalResidual{&interval, inv_sigma, params.estimate_sideslip});
    problem.AddResidualBlock(cost, new ceres::HuberLoss(params.huber_sigmas), p, offset, sideslip);
  }
  if (!params.estimate_time_offset) problem.SetParameterBlockConstant(offset);
  if (!params.estimate_sideslip) problem.SetParameterBlockConstant(sideslip);
}

// Unrobustified residual noise per axis, with 3n - m degrees of freedom spread over 3 axes.
Eigen::Vector3d residualSigma(ceres::Problem& problem, const Eigen::Vector3d& sigma, int n, int m) {
  ceres::Problem::EvaluateOptions options;
  options.apply_loss_function = false;
  std::vector<double> residuals;
  problem.Evaluate(options, nullptr, &residuals, nullptr, nullptr);
  Eigen::Vector3d sq = Eigen::Vector3d::Zero();
  for (int k = 0; k < n; ++k)
    for (int i = 0; i < 3; ++i) sq(i) += std::pow(residuals[3 * k + i] * sigma(i), 2);
  const double dof = std::max(1.0, (3.0 * n - m) / 3.0);
  return (sq / dof).cwiseSqrt();
}

// Whitened residuals and their Jacobian w.r.t. `blocks`, without the loss function.
Eigen::MatrixXd whitenedJacobian(ceres::Problem& problem, std::vector<double*> blocks,
                                 std::vector<double>* residuals = nullptr) {
  ceres::Problem::EvaluateOptions options;
  options.apply_loss_function = false;
  options.parameter_blocks = std::move(blocks);
  ceres::CRSMatrix crs;
  problem.Evaluate(options, nullptr, residuals, nullptr, &crs);
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(crs.num_rows, crs.num_cols);
  for (int r = 0; r < crs.num_rows; ++r)
    for (int k = crs.rows[r]; k < crs.rows[r + 1]; ++k) J(r, crs.cols[k]) = crs.values[k];
  return J;
}

// Sandwich C B C around Ceres' covariance C = (J^T J)^-1 of the whitened problem: B weighs each
// axis' rows by f = (1 + 2 rho) (sigma_residual / sigma_whitening)^2, the long-run variance of
// that axis' residuals (consecutive scan matches share a scan, so their errors partly cancel)
// in units of the variance the problem was whitened with. B = J^T J when f = 1.
Eigen::MatrixXd longRunCovariance(const Eigen::MatrixXd& C, const Eigen::MatrixXd& J,
                                  const std::vector<double>& residuals,
                                  const std::vector<CalibrationInterval>& intervals,
                                  const Eigen::Vector3d& sigma_whitening,
                                  const Eigen::Vector3d& sigma_residual,
                                  const std::vector<LoopSpan>& heading_loops) {
  const auto n = static_cast<Eigen::Index>(intervals.size());
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(J.cols(), J.cols());
  for (int axis = 0; axis < 3; ++axis) {
    std::vector<double> r(n);
    Eigen::MatrixXd J_axis(n, J.cols());
    for (Eigen::Index k = 0; k < n; ++k) {
      r[k] = residuals[3 * k + axis];
      J_axis.row(k) = J.row(3 * k + axis);
    }
    const double ratio = sigma_residual(axis) / sigma_whitening(axis);
    const double f = adjacentCorrelationFactor(intervals, r);
    if (axis == 2 && !heading_loops.empty()) {  // r over one match's heading sigma
      for (double& r_k : r) r_k /= ratio;
      B += ratio * ratio * loopScoreCovariance(intervals, heading_loops, J_axis, r, f);
      continue;
    }
    B += f * ratio * ratio * J_axis.transpose() * J_axis;
  }
  return C * B * C;
}

// The sandwich C (sum_k psi_k psi_k^T) C of the Huber fit (intervalOuterSum), psi_k = w_k J_k^T
// r_k interval k's gradient of the cost, w_k = min(1, a / |r_k|) the Huber weight: like
// twoStageSandwich, it holds whatever each interval's noise variance.
Eigen::MatrixXd huberSandwich(const Eigen::MatrixXd& C, const Eigen::MatrixXd& J,
                              const std::vector<double>& residuals,
                              const std::vector<CalibrationInterval>& intervals, double huber) {
  const auto n = static_cast<Eigen::Index>(intervals.size());
  std::vector<Eigen::VectorXd> psi(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Vector3d r(residuals[3 * k], residuals[3 * k + 1], residuals[3 * k + 2]);
    const double w = r.norm() > huber ? huber / r.norm() : 1.0;
    psi[k] = w * J.middleRows<3>(3 * k).transpose() * r;
  }
  return C * intervalOuterSum(intervals, psi, J.cols()) * C;
}

/// True, with the reason in result, when Ceres cannot start: the closed form refused, or both
/// extra scalars were asked for.
bool refusedBeforeSolving(const JointResult& start, const CeresParams& params,
                          CeresResult& result) {
  if (!start.ok) {
    result.reason = "closed-form start (joint) refused: " + start.reason;
    result.condition_number = start.condition_number;
    return true;
  }
  if (params.estimate_time_offset && params.estimate_sideslip) {
    result.reason = "the time offset and the sideslip cannot be estimated together";
    return true;
  }
  return false;
}

/// The first pass's whitening: the closed form's noise, translation sigmas pooled over x and y.
Eigen::Vector3d startSigma(const JointResult& start, const CeresParams& params) {
  const double sigma_t =
      std::sqrt(0.5 * (start.sigma_x_m * start.sigma_x_m + start.sigma_y_m * start.sigma_y_m));
  Eigen::Vector3d sigma(sigma_t, sigma_t, start.sigma_theta_rad);
  return sigma.cwiseMax(params.min_sigma);
}

ceres::Solver::Options solverOptions(const CeresParams& params) {
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = params.max_iterations;
  options.function_tolerance = 1e-14;
  options.gradient_tolerance = 1e-14;
  options.parameter_tolerance = 1e-14;
  options.num_threads = 1;
  return options;
}

std::string unidentifiableReason(double condition_number, const CeresParams& params) {
  return "parameters not identifiable (condition number " + std::to_string(condition_number) + ")" +
         (params.estimate_time_offset
              ? ": the time offset needs wheel rates that change across interval "
                "boundaries (mean-rate records cannot determine it)"
              : "");
}

/// Ceres' covariance C = (J^T J)^-1 of p and, when estimated, the extra scalar after it (an
/// m_blocks square); false when J^T J is rank deficient.
bool blockCovariance(ceres::Problem& problem, double* p, double* extra, int m_blocks,
                     Eigen::MatrixXd& C) {
  ceres::Covariance::Options cov_options;
  cov_options.algorithm_type = ceres::DENSE_SVD;
  cov_options.num_threads = 1;
  ceres::Covariance covariance(cov_options);
  std::vector<std::pair<const double*, const double*>> pairs = {{p, p}};
  if (extra) pairs.insert(pairs.end(), {{p, extra}, {extra, extra}});
  if (!covariance.Compute(pairs, &problem)) return false;
  C = Eigen::MatrixXd::Zero(m_blocks, m_blocks);
  Eigen::Matrix<double, 6, 6, Eigen::RowMajor> cov_pp;
  covariance.GetCovarianceBlock(p, p, cov_pp.data());
  C.topLeftCorner<6, 6>() = cov_pp;
  if (extra) {
    Eigen::Matrix<double, 6, 1> cov_pe;
    covariance.GetCovarianceBlock(p, extra, cov_pe.data());
    covariance.GetCovarianceBlock(extra, extra, &C(6, 6));
    C.block<6, 1>(0, 6) = cov_pe;
    C.block<1, 6>(6, 0) = cov_pe.transpose();
  }
  return true;
}

/// The final pass's verdict and covariance: condition number, convergence, identifiability,
/// then the long-run covariance of p (and the extra scalar's sigma). False: refused.
bool finalCovariance(ceres::Problem& problem, const ceres::Solver::Summary& summary,
                     const std::vector<CalibrationInterval>& intervals, const CeresParams& params,
                     const Eigen::Vector3d& sigma, const Eigen::Vector3d& refined, double* p,
                     double* extra, CeresResult& result) {
  std::vector<double*> blocks = {p};
  if (extra) blocks.push_back(extra);
  std::vector<double> residuals;
  const Eigen::MatrixXd J = whitenedJacobian(problem, blocks, &residuals);
  result.condition_number = equilibratedConditionNumber(J);
  if (summary.termination_type != ceres::CONVERGENCE) {
    result.reason = "Ceres did not converge: " + summary.BriefReport();
    return false;
  }
  if (!(result.condition_number <= params.max_condition_number)) {
    result.reason = unidentifiableReason(result.condition_number, params);
    return false;
  }
  Eigen::MatrixXd C;
  if (!blockCovariance(problem, p, extra, static_cast<int>(J.cols()), C)) {
    result.reason = "covariance rank deficient: parameters not identifiable from these intervals";
    return false;
  }
  Eigen::MatrixXd cov =
      longRunCovariance(C, J, residuals, intervals, sigma, refined, params.heading_loops);
  if (params.heading_loops.empty()) {  // with loops, longRunCovariance is a sandwich already
    cov = sandwichFloor(cov, huberSandwich(C, J, residuals, intervals, params.huber_sigmas),
                        result.sigma_sandwich_factors);
    result.sigma_sandwich_factors.resize(6);
  }
  result.covariance = cov.topLeftCorner<6, 6>();
  const double extra_sigma = extra ? std::sqrt(std::max(0.0, cov(6, 6))) : 0.0;
  if (params.estimate_time_offset) result.time_offset_sigma_s = extra_sigma;
  if (params.estimate_sideslip) result.sideslip_sigma_s = extra_sigma;
  return true;
}

}  // namespace

CeresResult calibrateCeres(const std::vector<CalibrationInterval>& intervals,
                           const CeresParams& params) {
  return calibrateCeres(intervals, calibrateJoint(intervals, params.start), params);
}

CeresResult calibrateCeres(const std::vector<CalibrationInterval>& intervals,
                           const JointResult& start, const CeresParams& params) {
  CeresResult result;
  result.estimates_mount = true;
  if (refusedBeforeSolving(start, params, result)) return result;
  const int n = static_cast<int>(intervals.size());
  const int m = 6 + (params.estimate_time_offset ? 1 : 0) + (params.estimate_sideslip ? 1 : 0);
  double p[6] = {start.geometry.radius_left_m, start.geometry.radius_right_m,
                 start.geometry.wheel_base_m,  start.T_base_lidar.x,
                 start.T_base_lidar.y,         start.T_base_lidar.yaw};
  double offset = 0.0;
  double sideslip = params.estimate_sideslip ? start.sideslip_s : 0.0;  // 0 unless joint had it
  // The estimated scalars beside p: the time offset or the sideslip (never both).
  double* extra = params.estimate_time_offset ? &offset
                  : params.estimate_sideslip  ? &sideslip
                                              : nullptr;
  Eigen::Vector3d sigma = startSigma(start, params);
  // Two passes: whiten with the closed form's noise estimate, then with the refined residuals'.
  ceres::Solver::Summary summary;
  for (int pass = 0; pass < 2; ++pass) {
    ceres::Problem problem;
    buildProblem(intervals, sigma, params, p, &offset, &sideslip, problem);
    ceres::Solve(solverOptions(params), &problem, &summary);
    result.iterations += static_cast<int>(summary.iterations.size());
    const Eigen::Vector3d refined = residualSigma(problem, sigma, n, m).cwiseMax(params.min_sigma);
    if (pass == 0) {
      sigma = refined;
      continue;
    }
    result.sigma_residual = refined;
    result.termination = ceres::TerminationTypeToString(summary.termination_type);
    result.cost = 2.0 * summary.final_cost;
    if (!finalCovariance(problem, summary, intervals, params, sigma, refined, p, extra, result))
      return result;
  }
  result.geometry = {p[0], p[1], p[2]};
  result.T_base_lidar = SE2(p[3], p[4], p[5]);
  result.time_offset_s = offset;
  result.sideslip_s = sideslip;
  result.intervals_used = n;
  if (!(p[0] > 0.0 && p[1] > 0.0 && p[2] > 0.0)) {
    result.reason = "refinement left the feasible region (a radius or b <= 0)";
    return result;
  }
  result.ok = true;
  return result;
}

}  // namespace slamprep::algo
