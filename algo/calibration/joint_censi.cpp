#include "slamprep/algo/calibration/joint_censi.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <optional>

namespace slamprep::algo {
namespace {

Eigen::Matrix2d rot(double a) {
  return (Eigen::Matrix2d() << std::cos(a), -std::sin(a), std::sin(a), std::cos(a)).finished();
}

// Residual rows of one interval, linear in x = [b, l_x, l_y, cos l_th, sin l_th].
// From T_base_lidar * sm_k = o_k * T_base_lidar, translation part:
//   t_l + R(l_th) s_t = b c_k + R(o_th) t_l
//   =>  -c_k b + (I - R(o_th)) t_l + [[s_x, -s_y], [s_y, s_x]] (cos l_th, sin l_th) = 0.   (Eq. 1)
// (The rotation part, l_th + s_th = o_th + l_th, is stage 1.) With a sideslip k (kLinear = 4)
// the odometry translation gains m d_k, m = k b (unitOdometry), one more linear unknown:
// x = [b, l_x, l_y, m, cos l_th, sin l_th] and the row gains -d_k m.
template <int kLinear>
Eigen::Matrix<double, 2, kLinear + 2> residualRows(const CalibrationInterval& interval, double J21,
                                                   double J22) {
  const UnitOdometry u = unitOdometry(interval, J21, J22);
  const SE2& s = interval.T_lidarStart_lidarEnd;
  Eigen::Matrix<double, 2, kLinear + 2> L;
  L.col(0) = -u.c;
  L.template block<2, 2>(0, 1) = Eigen::Matrix2d::Identity() - rot(u.o_th);
  if constexpr (kLinear == 4) L.col(3) = -u.d;
  L.template block<2, 2>(0, kLinear) << s.x, -s.y, s.y, s.x;
  return L;
}

// With the sideslip: k = m / b and its 1-sigma from the covariance over (J21, J22, b, l_x, l_y,
// m, l_th).
double sideslipSigma(const Eigen::MatrixXd& cov, double m, double b) {
  constexpr int kB = 2, kM = 5;
  Eigen::RowVectorXd dk = Eigen::RowVectorXd::Zero(cov.cols());
  dk(kB) = -m / (b * b);
  dk(kM) = 1.0 / b;
  return std::sqrt(std::max(0.0, (dk * cov * dk.transpose())(0, 0)));
}

// That covariance without m, i.e. marginalised over it.
Eigen::MatrixXd withoutSideslip(const Eigen::MatrixXd& cov) {
  const std::vector<int> keep = {0, 1, 2, 3, 4, 6};
  Eigen::MatrixXd out(6, 6);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) out(i, j) = cov(keep[i], keep[j]);
  return out;
}

// ---- Stage 2 of Censi et al. 2013, step by step ------------------------------------------------

/// Step 1, the quadratic form: Eq. 1 stacked over the intervals, L x = 0 with row pair k from
/// interval k, so the squared residual is |L x|^2 = x^T M x with M = L^T L.
template <int kLinear>
Eigen::MatrixXd stackResidualRows(const std::vector<CalibrationInterval>& intervals, double J21,
                                  double J22) {
  const auto n = static_cast<Eigen::Index>(intervals.size());
  Eigen::MatrixXd L(2 * n, kLinear + 2);
  for (Eigen::Index k = 0; k < n; ++k)
    L.middleRows<2>(2 * k) = residualRows<kLinear>(intervals[k], J21, J22);
  return L;
}

/// The constrained minimum x = [y; z] of x^T M x and its Lagrange multiplier.
template <int kLinear>
struct UnitCircleMinimum {
  Eigen::Matrix<double, kLinear, 1> y;  ///< (b, l_x, l_y[, m])
  Eigen::Vector2d z;                    ///< (cos l_th, sin l_th)
  double lambda = 0.0;

  double mountYaw() const { return std::atan2(z.y(), z.x()); }  // l_th
};

/// Step 2, the constrained minimisation: minimise x^T M x subject to x^T W x = 1,
/// W = diag(0, 0, 0, 1, 1). Lagrangian x^T M x + lambda (x^T W x - 1); stationarity
/// (M + lambda W) x = 0 needs a non-zero kernel, det(M + lambda W) = 0, and the cost there is
/// x^T M x = -lambda x^T W x = -lambda. Partition x = [y; z], y = (b, l_x, l_y), z = (cos, sin),
/// M = [[A, B], [B^T, D]]. The first block row gives y = -A^-1 B z (A is invertible: checked by
/// the caller). Substituting, (S + lambda I) z = 0 with the Schur complement
/// S = D - B^T A^-1 B, so det(M + lambda W) = det(A) det(S + lambda I) and
///   lambda^2 + tr(S) lambda + det(S) = 0,                                              (Eq. 2)
/// a quadratic whose roots are -mu_i, mu_i the eigenvalues of the symmetric 2x2 S. The cost at a
/// stationary point is -lambda = z^T S z = mu_i (|z| = 1), so the minimum is the smallest
/// eigenvalue mu_0 (lambda = -mu_0) with z its unit eigenvector; -z is the same stationary point
/// with y negated, and the sign is fixed by b > 0.
template <int kLinear>
UnitCircleMinimum<kLinear> minimiseOnUnitCircle(
    const Eigen::Matrix<double, kLinear + 2, kLinear + 2>& M) {
  using MatrixA = Eigen::Matrix<double, kLinear, kLinear>;
  const MatrixA A = M.template topLeftCorner<kLinear, kLinear>();
  const Eigen::Matrix<double, kLinear, 2> B = M.template topRightCorner<kLinear, 2>();
  const Eigen::LDLT<MatrixA> A_ldlt(A);
  const Eigen::Matrix2d S = M.template bottomRightCorner<2, 2>() - B.transpose() * A_ldlt.solve(B);
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(S);
  UnitCircleMinimum<kLinear> out;
  out.z = eig.eigenvectors().col(0).normalized();
  out.y = -A_ldlt.solve(B * out.z);
  if (out.y.x() < 0.0) {
    out.y = -out.y;
    out.z = -out.z;
  }
  out.lambda = -eig.eigenvalues()(0);
  return out;
}

/// Step 3, the recovery of the parameters: b = y_1, r_L = -J21 b, r_R = J22 b (J21 = -r_L / b,
/// J22 = r_R / b from stage 1), the mount position (y_2, y_3) and l_th = atan2(z_2, z_1).
/// False (with the reason) when b is not positive.
template <int kLinear>
bool recoverParameters(const UnitCircleMinimum<kLinear>& s, const RotationFit& stage1,
                       JointResult& result) {
  const double b = s.y.x();
  if (!(b > 0.0)) {
    result.reason = "stage 2 gives b = 0: the translations carry no information on b";
    return false;
  }
  result.geometry = {-stage1.J21 * b, stage1.J22 * b, b};
  result.T_base_lidar = SE2(s.y(1), s.y(2), s.mountYaw());
  return true;
}

/// Step 4a: the stage-2 Jacobian G of the residuals w.r.t. (b, l_x, l_y, [m,] l_th): L's linear
/// columns, and d/dl_th of R(l_th) s_t for the last.
template <int kLinear>
Eigen::MatrixXd stage2Jacobian(const std::vector<CalibrationInterval>& intervals,
                               const Eigen::MatrixXd& L, const Eigen::Vector2d& z) {
  const auto n = static_cast<Eigen::Index>(intervals.size());
  const Eigen::Matrix2d dR = (Eigen::Matrix2d() << -z.y(), -z.x(), z.x(), -z.y()).finished();
  Eigen::MatrixXd G(2 * n, kLinear + 1);
  for (Eigen::Index k = 0; k < n; ++k) {
    G.block(2 * k, 0, 2, kLinear) = L.block(2 * k, 0, 2, kLinear);
    G.block(2 * k, kLinear, 2, 1) = dR * intervals[k].T_lidarStart_lidarEnd.translation();
  }
  return G;
}

/// Translation noise of the scan matches, per lidar axis, and its long-run covariance.
struct TranslationNoise {
  Eigen::Vector2d var = Eigen::Vector2d::Zero();  ///< per axis, from the residuals
  Eigen::Matrix2d cov_n;  ///< long-run covariance of one residual, in the base-aligned frame
};

/// Step 4b: translation noise in the lidar frame: e_k = R(l_th) n_k to first order.
template <int kLinear>
TranslationNoise translationNoise(const std::vector<CalibrationInterval>& intervals,
                                  const Eigen::VectorXd& e, double l_th) {
  const auto n = static_cast<Eigen::Index>(intervals.size());
  const Eigen::Matrix2d R_l = rot(l_th);
  TranslationNoise out;
  Eigen::Vector2d& var = out.var;
  for (Eigen::Index k = 0; k < n; ++k) var += (R_l.transpose() * e.segment<2>(2 * k)).cwiseAbs2();
  var /= std::max(1.0, (2.0 * static_cast<double>(n) - (kLinear + 1)) / 2.0);  // dof, two axes
  // Consecutive scan matches share a scan: their errors partly cancel along the chain.
  std::vector<double> e_x(n), e_y(n);
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Vector2d e_lidar = R_l.transpose() * e.segment<2>(2 * k);
    e_x[k] = e_lidar.x();
    e_y[k] = e_lidar.y();
  }
  const Eigen::Vector2d var_long_run(var.x() * adjacentCorrelationFactor(intervals, e_x),
                                     var.y() * adjacentCorrelationFactor(intervals, e_y));
  out.cov_n = R_l * var_long_run.asDiagonal() * R_l.transpose();
  return out;
}

/// Step 4c: the covariance of (J21, J22, b, l_x, l_y, [m,] l_th): Fisher information of stage 2
/// (sandwich for the unweighted fit) and its dependence on stage 1 (central differences of the
/// residuals in J21, J22), combined by twoStageCovariance; `sumGtF` gets sum_k G_k^T F_k.
template <int kLinear>
Eigen::MatrixXd stage2Covariance(const std::vector<CalibrationInterval>& intervals,
                                 const RotationFit& stage1, const Eigen::MatrixXd& G,
                                 const Eigen::Matrix<double, kLinear + 2, 1>& x,
                                 const Eigen::Matrix2d& cov_n, Eigen::MatrixXd& sumGtF) {
  const auto n = static_cast<Eigen::Index>(intervals.size());
  const double h = 1e-6 * std::max(std::abs(stage1.J21), std::abs(stage1.J22));
  Eigen::Matrix<double, kLinear + 1, kLinear + 1> N;
  N.setZero();
  sumGtF = Eigen::MatrixXd::Zero(kLinear + 1, 2);
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto Gk = G.middleRows<2>(2 * k);
    N += Gk.transpose() * cov_n * Gk;
    Eigen::Matrix2d F;
    F.col(0) = (residualRows<kLinear>(intervals[k], stage1.J21 + h, stage1.J22) -
                residualRows<kLinear>(intervals[k], stage1.J21 - h, stage1.J22)) *
               x / (2 * h);
    F.col(1) = (residualRows<kLinear>(intervals[k], stage1.J21, stage1.J22 + h) -
                residualRows<kLinear>(intervals[k], stage1.J21, stage1.J22 - h)) *
               x / (2 * h);
    sumGtF += Gk.transpose() * F;
  }
  const Eigen::MatrixXd H = G.transpose() * G;
  return twoStageCovariance(stage1.covariance, H, N, sumGtF);
}

/// Each interval's squared residual, rotation and translation each over its noise variance.
std::vector<double> normalisedScores(const RotationFit& stage1, const Eigen::VectorXd& e,
                                     const Eigen::Vector2d& var) {
  const Eigen::Index n = e.size() / 2;
  const double var_t = std::max(0.5 * (var.x() + var.y()), 1e-300);
  const double var_th = std::max(stage1.sigma_theta_rad * stage1.sigma_theta_rad, 1e-300);
  std::vector<double> scores(n);
  for (Eigen::Index k = 0; k < n; ++k)
    scores[k] = stage1.residuals_rad[k] * stage1.residuals_rad[k] / var_th +
                e.segment<2>(2 * k).squaredNorm() / var_t;
  return scores;
}

/// Stage 1 (the rotation fit) into the result; false (with the reason) when it refused.
bool takeRotationFit(const RotationFit& stage1, JointResult& result) {
  result.condition_number = stage1.condition_number;
  result.J21 = stage1.J21;
  result.J22 = stage1.J22;
  result.sigma_theta_rad = stage1.sigma_theta_rad;
  result.rotation_heteroscedasticity = stage1.turn_heteroscedasticity;
  if (!stage1.ok) result.reason = stage1.reason;
  return stage1.ok;
}

/// The sandwich of the two stages (twoStageSandwich); none where loop closures corrected the
/// headings, whose covariance (loop_covariance.hpp) is already a sandwich of its own.
std::optional<Eigen::MatrixXd> sandwichOf(const std::vector<CalibrationInterval>& intervals,
                                          const RotationFit& stage1, const Eigen::MatrixXd& G,
                                          const Eigen::VectorXd& e, const Eigen::MatrixXd& sumGtF,
                                          const JointParams& params) {
  if (!params.heading_loops.empty()) return std::nullopt;
  return twoStageSandwich(intervals, stage1.residuals_rad, G, e, sumGtF);
}

/// The result's covariance over (r_L, r_R, b, l_x, l_y, l_th) from that over (J21, J22, b, l_x,
/// l_y, [m,] l_th), never below the sandwich's (sandwichFloor); with the sideslip, its sigma too.
template <int kLinear>
void setCovariance(const Eigen::MatrixXd& cov_J, const std::optional<Eigen::MatrixXd>& sandwich_J,
                   const UnitCircleMinimum<kLinear>& s, JointResult& result) {
  const double b = s.y.x();
  auto userSpace = [&](const Eigen::MatrixXd& c) {
    if constexpr (kLinear == 4)
      return radiiCovariance(withoutSideslip(c), result.J21, result.J22, b);
    return radiiCovariance(c, result.J21, result.J22, b);
  };
  result.covariance = userSpace(cov_J);
  if constexpr (kLinear == 4) {
    result.sideslip_s = s.y(3) / b;
    result.sideslip_sigma_s = sideslipSigma(cov_J, s.y(3), b);
    if (sandwich_J)
      result.sideslip_sigma_s =
          std::max(result.sideslip_sigma_s, sideslipSigma(*sandwich_J, s.y(3), b));
  }
  if (sandwich_J)
    result.covariance =
        sandwichFloor(result.covariance, userSpace(*sandwich_J), result.sigma_sandwich_factors);
}

// One fit on a fixed set of intervals; `scores` gets each interval's normalised squared residual.
// kLinear: the unknowns of Eq. 1 besides (cos, sin): 3 (b, l_x, l_y), 4 with the sideslip.
template <int kLinear>
JointResult fitOnce(const std::vector<CalibrationInterval>& intervals, const JointParams& params,
                    std::vector<double>* scores) {
  JointResult result;
  const auto n = static_cast<Eigen::Index>(intervals.size());
  const RotationFit stage1 =
      fitRotation(intervals, params.max_condition_number, params.heading_loops);
  if (!takeRotationFit(stage1, result)) return result;
  constexpr int kX = kLinear + 2;  // x = [linear unknowns, cos l_th, sin l_th]
  // Step 1, the quadratic form x^T M x (Eq. 1 stacked), once A in M is invertible.
  const Eigen::MatrixXd L = stackResidualRows<kLinear>(intervals, stage1.J21, stage1.J22);
  const double cond_bl = equilibratedConditionNumber(L.leftCols(kLinear));
  result.condition_number = std::max(result.condition_number, cond_bl);
  if (!(cond_bl <= params.max_condition_number)) {
    result.reason = "b and the mount position are not determined (condition number " +
                    std::to_string(cond_bl) + "): " + describeDegenerateDriving(intervals);
    return result;
  }
  const Eigen::Matrix<double, kX, kX> M = L.transpose() * L;
  // Step 2, the constrained minimisation (Eq. 2); step 3, the parameters from x.
  const UnitCircleMinimum<kLinear> s = minimiseOnUnitCircle<kLinear>(M);
  result.lambda = s.lambda;
  if (!recoverParameters(s, stage1, result)) return result;
  // Step 4, the covariance: G at x, the noise of e = L x, then stage 1 and 2 combined.
  Eigen::Matrix<double, kX, 1> x;
  x << s.y, s.z;
  const Eigen::MatrixXd G = stage2Jacobian<kLinear>(intervals, L, s.z);
  const Eigen::VectorXd e = L * x;  // the residuals at the solution
  result.condition_number = std::max(result.condition_number, equilibratedConditionNumber(G));
  if (!(result.condition_number <= params.max_condition_number)) {
    result.reason = "the mount yaw is not determined (condition number " +
                    std::to_string(result.condition_number) +
                    "): " + describeDegenerateDriving(intervals);
    return result;
  }
  const TranslationNoise noise = translationNoise<kLinear>(intervals, e, s.mountYaw());
  result.sigma_x_m = std::sqrt(noise.var.x());
  result.sigma_y_m = std::sqrt(noise.var.y());
  Eigen::MatrixXd sumGtF;
  const Eigen::MatrixXd cov_J =
      stage2Covariance<kLinear>(intervals, stage1, G, x, noise.cov_n, sumGtF);
  setCovariance<kLinear>(cov_J, sandwichOf(intervals, stage1, G, e, sumGtF, params), s, result);
  result.estimates_mount = true;
  result.cost = e.squaredNorm();
  result.intervals_used = static_cast<int>(n);
  if (scores) *scores = normalisedScores(stage1, e, noise.var);
  result.ok = true;
  return result;
}

}  // namespace

JointResult calibrateJoint(const std::vector<CalibrationInterval>& intervals,
                           const JointParams& params) {
  const int min_n = std::max(params.min_intervals, kMinIntervalsAbsolute);
  std::vector<int> used(intervals.size());
  std::iota(used.begin(), used.end(), 0);
  auto subset = [&] {
    std::vector<CalibrationInterval> out;
    for (int i : used) out.push_back(intervals[i]);
    return out;
  };
  if (static_cast<int>(intervals.size()) < min_n) {
    JointResult result;
    result.reason = "too few intervals: " + std::to_string(intervals.size()) + " (need at least " +
                    std::to_string(min_n) + ")";
    return result;
  }
  std::vector<double> scores;
  auto fit = [&params](const std::vector<CalibrationInterval>& subset, std::vector<double>* out) {
    return params.estimate_sideslip ? fitOnce<4>(subset, params, out)
                                    : fitOnce<3>(subset, params, out);
  };
  JointResult result = fit(intervals, &scores);
  int round = 0;
  for (; round < params.trim_rounds && result.ok; ++round) {
    const int drop = static_cast<int>(params.trim_fraction * static_cast<double>(used.size()));
    if (drop <= 0 || static_cast<int>(used.size()) - drop < min_n) break;
    std::vector<int> order(used.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return scores[a] < scores[b]; });
    order.resize(used.size() - drop);
    std::sort(order.begin(), order.end());
    std::vector<int> kept;
    for (int i : order) kept.push_back(used[i]);
    used = std::move(kept);
    result = fit(subset(), &scores);
  }
  result.iterations = round;
  result.intervals_trimmed = static_cast<int>(intervals.size() - used.size());
  result.used = used;
  return result;
}

}  // namespace slamprep::algo
