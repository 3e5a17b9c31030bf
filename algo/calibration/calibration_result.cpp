#include "slamprep/algo/calibration/calibration_result.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace slamprep::algo {
namespace {

std::string formatJ(double J21, double J22) {
  std::ostringstream s;
  s.precision(4);
  s << "J21 = " << J21 << ", J22 = " << J22;
  return s.str();
}

}  // namespace

Eigen::VectorXd calibrationValues(const CalibrationResult& r) {
  Eigen::VectorXd v(r.estimates_mount ? 6 : 3);
  v.head<3>() << r.geometry.radius_left_m, r.geometry.radius_right_m, r.geometry.wheel_base_m;
  if (r.estimates_mount) v.tail<3>() << r.T_base_lidar.x, r.T_base_lidar.y, r.T_base_lidar.yaw;
  return v;
}

Eigen::VectorXd CalibrationResult::sigma() const {
  const int n = estimates_mount ? 6 : 3;
  if (covariance.rows() != n || covariance.cols() != n) return Eigen::VectorXd::Zero(n);
  return covariance.diagonal().cwiseMax(0.0).cwiseSqrt();
}

double equilibratedConditionNumber(const Eigen::MatrixXd& A) {
  const double inf = std::numeric_limits<double>::infinity();
  if (A.rows() < A.cols() || A.cols() == 0) return inf;
  Eigen::MatrixXd scaled = A;
  for (Eigen::Index j = 0; j < A.cols(); ++j) {
    const double norm = A.col(j).norm();
    if (!(norm > 0.0) || !std::isfinite(norm)) return inf;
    scaled.col(j) /= norm;
  }
  const Eigen::VectorXd s = Eigen::JacobiSVD<Eigen::MatrixXd>(scaled).singularValues();
  const double smin = s(s.size() - 1);
  return smin > s(0) * 1e-15 ? s(0) / smin : inf;
}

std::string describeDegenerateDriving(const std::vector<CalibrationInterval>& intervals) {
  // With roughly equal radii, sum dphi_L + sum dphi_R measures driving and the difference turning.
  bool all_straight = true, all_spin = true;
  for (const CalibrationInterval& interval : intervals) {
    const double l = interval.sumLeft_rad(), r = interval.sumRight_rad();
    const double scale = std::abs(l) + std::abs(r);
    if (std::abs(r - l) > 0.05 * scale) all_straight = false;
    if (std::abs(r + l) > 0.05 * scale) all_spin = false;
  }
  if (all_straight)
    return "straight-line-only driving: the robot never turned, so the wheel base and the "
           "radius ratio cannot be determined; add turns and spins";
  if (all_spin)
    return "spin-only driving: the robot never translated, so the wheel radii cannot be "
           "separated from the wheel base; add straight or curved driving";
  return "the wheel rotations of all intervals are (nearly) proportional (a single curvature): "
         "drive at least two different curvatures, e.g. a figure eight plus spins";
}

double adjacentCorrelationFactor(const std::vector<CalibrationInterval>& intervals,
                                 const std::vector<double>& residuals) {
  double sum_sq = 0.0, sum_lag = 0.0;
  int adjacent = 0;
  for (std::size_t k = 0; k < residuals.size(); ++k) {
    sum_sq += residuals[k] * residuals[k];
    if (k + 1 < residuals.size() &&
        std::abs(intervals[k].t_end_s - intervals[k + 1].t_start_s) <= 1e-9) {
      sum_lag += residuals[k] * residuals[k + 1];
      ++adjacent;
    }
  }
  if (adjacent == 0 || !(sum_sq > 0.0)) return 1.0;
  const double rho = (sum_lag / adjacent) / (sum_sq / static_cast<double>(residuals.size()));
  return 1.0 + 2.0 * std::clamp(rho, -0.45, 0.5);
}

double turnHeteroscedasticity(const Eigen::VectorXd& residual, const Eigen::VectorXd& predicted) {
  const Eigen::ArrayXd e2 = residual.array().square();
  const Eigen::ArrayXd x = predicted.array().square();
  const double n = double(e2.size());
  const Eigen::ArrayXd xc = x - x.mean(), yc = e2 - e2.mean();
  const double sxx = xc.square().sum(), syy = yc.square().sum();
  if (!(sxx > 0.0) || !(syy > 0.0)) return 0.0;
  const double sxy = (xc * yc).sum();
  return n * sxy * sxy / (sxx * syy);
}

namespace {

/// The rotation step's design: row k is interval k's (sum dphi_L, sum dphi_R).
Eigen::MatrixXd rotationDesign(const std::vector<CalibrationInterval>& intervals) {
  Eigen::MatrixXd A(static_cast<Eigen::Index>(intervals.size()), 2);
  for (Eigen::Index k = 0; k < A.rows(); ++k)
    A.row(k) << intervals[k].sumLeft_rad(), intervals[k].sumRight_rad();
  return A;
}

std::string wrongSignReason(const RotationFit& fit) {
  // A sign is only a finding 3 sigmas from zero; nearer, the wheels' turns do not follow the
  // scans' (a lifted or blocked robot on a short recording looked like a channel swap).
  const bool clear21 = std::abs(fit.J21) > 3.0 * std::sqrt(fit.covariance(0, 0));
  const bool clear22 = std::abs(fit.J22) > 3.0 * std::sqrt(fit.covariance(1, 1));
  const std::string j = formatJ(fit.J21, fit.J22) + " (r_L = -J21 b, r_R = J22 b)";
  const std::string unless =
      ", unless the wheels turned while the robot did not (a lifted or blocked robot: the "
      "sensor agreement names such spans)";
  if (fit.J21 > 0.0 && fit.J22 < 0.0 && clear21 && clear22)
    return "left/right encoder channels swapped: " + j + " gives negative radii; swap them" +
           unless;
  if ((fit.J21 > 0.0 && clear21) || (fit.J22 < 0.0 && clear22))
    return "negative wheel radius: " + j + "; one encoder counts backwards" + unless;
  return "undetermined: " + j +
         " has a sign that is not 3 sigmas from zero: the wheels' turns do not follow the "
         "scans' (too little turning, or wheels that turned while the robot did not)";
}

}  // namespace

RotationFit fitRotation(const std::vector<CalibrationInterval>& intervals, double max_condition,
                        const std::vector<LoopSpan>& heading_loops) {
  RotationFit fit;
  const auto n = static_cast<Eigen::Index>(intervals.size());
  const Eigen::MatrixXd A = rotationDesign(intervals);
  Eigen::VectorXd theta(n);
  for (Eigen::Index k = 0; k < n; ++k) theta(k) = intervals[k].T_lidarStart_lidarEnd.yaw;
  fit.condition_number = equilibratedConditionNumber(A);
  if (!(fit.condition_number <= max_condition)) {
    fit.reason = "rotation step ill-conditioned (condition number " +
                 (std::isfinite(fit.condition_number) ? std::to_string(fit.condition_number)
                                                      : std::string("inf")) +
                 "): " + describeDegenerateDriving(intervals);
    return fit;
  }
  const Eigen::Vector2d J = A.colPivHouseholderQr().solve(theta);  // normal eqs. without A^T A
  fit.J21 = J.x();
  fit.J22 = J.y();
  const Eigen::VectorXd res = theta - A * J;
  fit.residuals_rad.assign(res.data(), res.data() + n);
  const double dof = static_cast<double>(n - 2);
  fit.sigma_theta_rad = dof > 0 ? std::sqrt(res.squaredNorm() / dof) : 0.0;
  const double f = adjacentCorrelationFactor(intervals, fit.residuals_rad);
  const Eigen::Matrix2d AtA_inv = (A.transpose() * A).inverse();
  fit.covariance = f * fit.sigma_theta_rad * fit.sigma_theta_rad * AtA_inv;
  if (!heading_loops.empty() && fit.sigma_theta_rad > 0.0) {  // sandwich, loop-corrected score
    std::vector<double> normalized(fit.residuals_rad);
    for (double& r : normalized) r /= fit.sigma_theta_rad;
    fit.covariance = fit.sigma_theta_rad * fit.sigma_theta_rad * AtA_inv *
                     loopScoreCovariance(intervals, heading_loops, A, normalized, f) * AtA_inv;
  }
  fit.turn_heteroscedasticity = turnHeteroscedasticity(res, A * J);
  // r_L = -J21 b and r_R = J22 b must both be positive for b > 0.
  if (!(fit.J21 < 0.0 && fit.J22 > 0.0)) {
    fit.reason = wrongSignReason(fit);
    return fit;
  }
  fit.ok = true;
  return fit;
}

UnitOdometry unitOdometry(const CalibrationInterval& interval, double J21, double J22) {
  UnitOdometry out;
  for (const EncoderStep& step : interval.steps) {
    const double dth = J21 * step.dphi_left_rad + J22 * step.dphi_right_rad;
    const double ds_per_b = 0.5 * (-J21 * step.dphi_left_rad + J22 * step.dphi_right_rad);
    const double c = std::cos(out.o_th), s = std::sin(out.o_th);
    const Eigen::Vector2d local(ds_per_b * sinc(dth), ds_per_b * cosc(dth));
    out.c += Eigen::Vector2d(c * local.x() - s * local.y(), s * local.x() + c * local.y());
    if (step.dt_s > 0.0) {  // the sideways step exp((0, w, dth)) per unit m, w = ds dth / dt
      const double w = ds_per_b * dth / step.dt_s;
      const Eigen::Vector2d side(-w * cosc(dth), w * sinc(dth));
      out.d += Eigen::Vector2d(c * side.x() - s * side.y(), s * side.x() + c * side.y());
    }
    out.o_th += dth;
  }
  return out;
}

Eigen::MatrixXd twoStageCovariance(const Eigen::Matrix2d& cov1, const Eigen::MatrixXd& H,
                                   const Eigen::MatrixXd& N, const Eigen::MatrixXd& sumGtF) {
  const Eigen::Index m = H.rows();
  const Eigen::MatrixXd H_inv = H.inverse();  // m <= 5, checked well-conditioned by the caller
  const Eigen::MatrixXd K = -H_inv * sumGtF;
  Eigen::MatrixXd C(2 + m, 2 + m);
  C.topLeftCorner(2, 2) = cov1;
  C.bottomLeftCorner(m, 2) = K * cov1;
  C.topRightCorner(2, m) = (K * cov1).transpose();
  C.bottomRightCorner(m, m) = H_inv * N * H_inv + K * cov1 * K.transpose();
  return C;
}

Eigen::MatrixXd intervalOuterSum(const std::vector<CalibrationInterval>& intervals,
                                 const std::vector<Eigen::VectorXd>& v, Eigen::Index estimated) {
  const auto n = static_cast<Eigen::Index>(v.size());
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(v.front().size(), v.front().size());
  for (Eigen::Index k = 0; k < n; ++k) {
    S += v[k] * v[k].transpose();
    if (k + 1 < n && std::abs(intervals[k].t_end_s - intervals[k + 1].t_start_s) <= 1e-9)
      S += v[k] * v[k + 1].transpose() + v[k + 1] * v[k].transpose();
  }
  return S * (double(n) / double(std::max<Eigen::Index>(1, n - estimated)));
}

Eigen::MatrixXd twoStageSandwich(const std::vector<CalibrationInterval>& intervals,
                                 const std::vector<double>& rotation_residuals,
                                 const Eigen::MatrixXd& G, const Eigen::VectorXd& e,
                                 const Eigen::MatrixXd& sumGtF) {
  const auto n = static_cast<Eigen::Index>(intervals.size());
  const Eigen::Index m = G.cols();
  const Eigen::MatrixXd A = rotationDesign(intervals);
  const Eigen::Matrix2d AtA_inv = (A.transpose() * A).inverse();
  const Eigen::MatrixXd H_inv = (G.transpose() * G).inverse();
  const Eigen::MatrixXd K = -H_inv * sumGtF;
  std::vector<Eigen::VectorXd> d(n, Eigen::VectorXd(2 + m));
  for (Eigen::Index k = 0; k < n; ++k) {  // Eq. (S1)
    const Eigen::Vector2d dp1 = AtA_inv * A.row(k).transpose() * rotation_residuals[k];
    d[k] << dp1, -H_inv * G.middleRows(2 * k, 2).transpose() * e.segment<2>(2 * k) + K * dp1;
  }
  return intervalOuterSum(intervals, d, 2 + m);
}

Eigen::MatrixXd sandwichFloor(const Eigen::MatrixXd& model, const Eigen::MatrixXd& sandwich,
                              std::vector<double>& factors) {
  const Eigen::Index m = model.rows();
  factors.assign(m, 1.0);
  const Eigen::LLT<Eigen::MatrixXd> llt(model);
  if (llt.info() != Eigen::Success || !sandwich.allFinite()) return model;
  // In the model's whitened coordinates W = L^-1 S L^-T, raise the eigenvalues below 1 to 1.
  const Eigen::MatrixXd L = llt.matrixL();
  const Eigen::MatrixXd L_inv =
      L.triangularView<Eigen::Lower>().solve(Eigen::MatrixXd::Identity(m, m));
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(L_inv * sandwich * L_inv.transpose());
  const Eigen::VectorXd raised = eig.eigenvalues().cwiseMax(1.0);
  const Eigen::MatrixXd floored =
      L * eig.eigenvectors() * raised.asDiagonal() * eig.eigenvectors().transpose() * L.transpose();
  for (Eigen::Index i = 0; i < m; ++i) factors[i] = std::sqrt(floored(i, i) / model(i, i));
  return 0.5 * (floored + floored.transpose());
}

Eigen::MatrixXd radiiCovariance(const Eigen::MatrixXd& cov_J, double J21, double J22, double b) {
  Eigen::MatrixXd D = Eigen::MatrixXd::Identity(cov_J.rows(), cov_J.cols());
  D(0, 0) = -b;    // dr_L/dJ21
  D(0, 2) = -J21;  // dr_L/db
  D(1, 1) = b;     // dr_R/dJ22
  D(1, 2) = J22;   // dr_R/db
  return D * cov_J * D.transpose();
}

}  // namespace slamprep::algo
