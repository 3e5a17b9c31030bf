#include "slamprep/algo/calibration/model_based.hpp"

#include <Eigen/Dense>
#include <cmath>

namespace slamprep::algo {
namespace {

// b = argmin sum_k |s_k - b c_k|^2 = sum c.s / sum c.c  (the lecture's stacked c b = s).
double solveB(const std::vector<CalibrationInterval>& intervals, double J21, double J22,
              double* sum_cc) {
  double cs = 0.0, cc = 0.0;
  for (const CalibrationInterval& interval : intervals) {
    const Eigen::Vector2d c = unitOdometry(interval, J21, J22).c;
    cs += c.dot(interval.T_lidarStart_lidarEnd.translation());
    cc += c.squaredNorm();
  }
  if (sum_cc) *sum_cc = cc;
  return cc > 0.0 ? cs / cc : 0.0;
}

}  // namespace

ModelBasedResult calibrateModelBased(const std::vector<CalibrationInterval>& intervals,
                                     const ModelBasedParams& params) {
  ModelBasedResult result;
  const int n = static_cast<int>(intervals.size());
  if (n < std::max(params.min_intervals, kMinIntervalsAbsolute)) {
    result.reason = "too few intervals: " + std::to_string(n) + " (need at least " +
                    std::to_string(std::max(params.min_intervals, kMinIntervalsAbsolute)) + ")";
    return result;
  }
  const RotationFit rot = fitRotation(intervals, params.max_condition_number);
  result.condition_number = rot.condition_number;
  result.J21 = rot.J21;
  result.J22 = rot.J22;
  result.rotation_heteroscedasticity = rot.turn_heteroscedasticity;
  if (!rot.ok) {
    result.reason = rot.reason;
    return result;
  }
  double sum_cc = 0.0;
  const double b = solveB(intervals, rot.J21, rot.J22, &sum_cc);
  double travel = 0.0;  // total measured translation, for the spin test below
  for (const CalibrationInterval& interval : intervals)
    travel += interval.T_lidarStart_lidarEnd.translation().norm();
  if (!(b > 0.0) || !(sum_cc > 0.0)) {
    result.reason = travel > 0.0 ? "translation step gives b <= 0: encoder and lidar disagree "
                                   "on the driving direction (lidar mounted backwards?)"
                                 : "spin-only driving: no translation to determine b";
    return result;
  }
  result.geometry = {-rot.J21 * b, rot.J22 * b, b};

  // Covariance: e_k = s_k - b c_k(J); G_k = -c_k, F_k = -b dc_k/dJ (central differences).
  Eigen::Vector2d sq = Eigen::Vector2d::Zero();  // squared residuals per axis of the lidar frame
  Eigen::MatrixXd sumGtF = Eigen::MatrixXd::Zero(1, 2);
  Eigen::MatrixXd G(2 * n, 1);
  Eigen::VectorXd e(2 * n);
  const double h = 1e-6 * std::max(std::abs(rot.J21), std::abs(rot.J22));
  for (int k = 0; k < n; ++k) {
    const CalibrationInterval& interval = intervals[k];
    const Eigen::Vector2d c = unitOdometry(interval, rot.J21, rot.J22).c;
    G.middleRows<2>(2 * k) = -c;
    e.segment<2>(2 * k) = interval.T_lidarStart_lidarEnd.translation() - b * c;
    sq += e.segment<2>(2 * k).cwiseAbs2();
    Eigen::Matrix2d dc;
    dc.col(0) = (unitOdometry(interval, rot.J21 + h, rot.J22).c -
                 unitOdometry(interval, rot.J21 - h, rot.J22).c) /
                (2 * h);
    dc.col(1) = (unitOdometry(interval, rot.J21, rot.J22 + h).c -
                 unitOdometry(interval, rot.J21, rot.J22 - h).c) /
                (2 * h);
    sumGtF += (-c).transpose() * (-b * dc);
  }
  // Translation noise per axis (the scan matcher's x and y noise differ), with the 2n - 1
  // degrees of freedom split evenly over the two axes; N = sum_k c_k^T diag(var) c_k.
  const Eigen::Vector2d var = sq / (n - 0.5);
  double sum_cVc = 0.0;
  for (const CalibrationInterval& interval : intervals)
    sum_cVc += unitOdometry(interval, rot.J21, rot.J22).c.cwiseAbs2().dot(var);
  const Eigen::MatrixXd H = Eigen::MatrixXd::Constant(1, 1, sum_cc);
  const Eigen::MatrixXd N = Eigen::MatrixXd::Constant(1, 1, sum_cVc);
  result.covariance =
      radiiCovariance(twoStageCovariance(rot.covariance, H, N, sumGtF), rot.J21, rot.J22, b);
  const Eigen::MatrixXd sandwich = radiiCovariance(
      twoStageSandwich(intervals, rot.residuals_rad, G, e, sumGtF), rot.J21, rot.J22, b);
  result.covariance = sandwichFloor(result.covariance, sandwich, result.sigma_sandwich_factors);
  result.cost = sq.sum() + std::pow(rot.sigma_theta_rad, 2) * (n - 2);
  result.intervals_used = n;
  result.iterations = 1;
  result.ok = true;
  return result;
}

}  // namespace slamprep::algo
