#pragma once
// Several recordings of one robot, each calibrated on its own, combined per method: the
// information-weighted mean of the estimates and how well they agree (docs/calibration.md,
// "Several recordings"). One recording's covariance cannot show what differs between
// recordings (a floor, a load, a matcher's drift); the scatter of several can.

#include <Eigen/Core>
#include <cmath>
#include <string>
#include <vector>

#include "slamprep/algo/calibration/calibrate.hpp"

namespace slamprep::algo {

struct CombineParams {
  /// Where chi2/dof of a parameter exceeds this, the recordings disagree beyond their sigmas:
  /// its combined sigma is scaled by sqrt(chi2/dof) and the output warns.
  double max_chi2_dof = 2.0;
};

/// The combination of n estimates x_i with covariances C_i (positive definite):
///   x = (sum C_i^-1)^-1 sum C_i^-1 x_i,  C = (sum C_i^-1)^-1                      Eq. (1)
///   chi2_dof_j = sum_i (x_ij - x_j)^2 / C_i,jj / (n - 1)   (n >= 2)               Eq. (2)
/// and, where chi2_dof_j > max_chi2_dof, row and column j of C scaled by sqrt(chi2_dof_j).
struct CombinedEstimate {
  bool ok = false;
  std::string reason;  ///< why not, when !ok
  Eigen::VectorXd values;
  Eigen::MatrixXd covariance;  ///< scaled where the estimates disagree
  /// Per parameter: Eq. (2), NaN when n < 2.
  Eigen::VectorXd chi2_dof;
  /// Per parameter: sqrt(chi2_dof) where it exceeds max_chi2_dof, else 1.
  Eigen::VectorXd sigma_scale;
  /// The input and parameter with the largest (x_ij - x_j)^2 / C_i,jj among the scaled
  /// parameters; -1 when none is scaled.
  int worst_input = -1;
  int worst_parameter = -1;
  int failed_input = -1;  ///< when !ok because of one input: its index
  /// Eq. (3) for r_L / b and r_R / b; NaN when n < 2 or there is no wheel base.
  Eigen::Vector2d ratio_chi2_dof = Eigen::Vector2d::Constant(std::nan(""));
};

/// What a drive pins down best is the rotation per wheel angle, q = r / b, not r or b alone:
/// they are strongly correlated, so r and b can each agree within their wide sigmas while q
/// does not (then Eq. (1)'s mean leaves the recordings' range along the poorly determined common
/// scale). Per wheel, with q_i = r_i / b_i and its variance by the delta method,
///   var q_i = g^T C_i g,  g = (1 / b, 0, -r_L / b^2) for the left wheel (0, 1 / b, -r_R / b^2
///   for the right),  chi2_dof = sum_i (q_i - q)^2 / var q_i / (n - 1),
///   q the inverse-variance weighted mean of the q_i                                  Eq. (3)
Eigen::Vector2d ratioConsistency(const std::vector<Eigen::VectorXd>& values,
                                 const std::vector<Eigen::MatrixXd>& covariances);

/// var q of Eq. (3) for one estimate (r_L, r_R, b, ...) with covariance C; wheel 0 left, 1 right.
double wheelRatioVariance(const Eigen::VectorXd& x, const Eigen::MatrixXd& C, int wheel);

/// Eq. (1) and (2). Refuses (ok = false) no estimates, a covariance that is not positive
/// definite, or estimates of different sizes.
CombinedEstimate combineEstimates(const std::vector<Eigen::VectorXd>& values,
                                  const std::vector<Eigen::MatrixXd>& covariances,
                                  const CombineParams& params = {});

/// One method's runs over the recordings combined.
struct CombinedRun {
  CalibrationRun run;         ///< the combined result in the usual form (method, geometry, ...)
  CombinedEstimate estimate;  ///< with chi2/dof per parameter
  /// Index into the runs given of every estimate combined (the ok runs), in order.
  std::vector<int> recordings;
};

/// Combines the ok runs of one method (`runs[i]`: recording i's run, nullptr when the method did
/// not run there). The lidar yaws are unwrapped onto the first one's before they are averaged.
/// The run refuses when no recording's run is ok or Eq. (1) refuses; with one ok run it is that
/// run's estimate (chi2/dof NaN).
CombinedRun combineRuns(CalibrationMethod method, const std::vector<const CalibrationRun*>& runs,
                        const CombineParams& params = {});

}  // namespace slamprep::algo
