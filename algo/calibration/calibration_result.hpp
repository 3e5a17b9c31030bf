#pragma once
// What every odometry calibration method reports, and the pieces the closed-form methods share.

#include <Eigen/Core>
#include <array>
#include <string>
#include <vector>

#include "slamprep/algo/calibration/interval.hpp"
#include "slamprep/algo/calibration/loop_covariance.hpp"
#include "slamprep/core/diff_drive.hpp"
#include "slamprep/core/se2.hpp"

namespace slamprep::algo {

/// An interval dropped as an outlier by the robust screening (robust_trim.hpp).
struct TrimmedInterval {
  double t0_s = 0.0;
  double t1_s = 0.0;
  std::string reason;            ///< which component disagreed with the fit, and by how much
  double residual_sigmas = 0.0;  ///< its robust score z (robust_trim.hpp, Eq. 2)
};

/// chi^2 with one degree of freedom at p = 0.001: where the rotation step's test rejects.
inline constexpr double kTurnHeteroscedasticityMinStatistic = 10.83;

/// The common part of every method's result. When ok is false, `reason` says why and the numbers
/// are not to be used (they are finite, never NaN).
struct CalibrationResult {
  bool ok = false;
  std::string reason;  ///< why the method refused; empty when ok
  /// Estimated r_L, r_R, b.
  DiffDriveParams geometry;
  /// True when the method estimates the lidar mount (joint, ceres).
  bool estimates_mount = false;
  /// Estimated T_base_lidar (identity when not estimated: the lidar is assumed at the centre).
  SE2 T_base_lidar;
  /// Covariance of (r_L, r_R, b) or, with the mount, (r_L, r_R, b, l_x, l_y, l_yaw); SI units.
  Eigen::MatrixXd covariance;
  /// Condition number of the (column-equilibrated) least-squares problem(s); the worst one.
  double condition_number = 0.0;
  int intervals_used = 0;  ///< intervals in the final fit (after trimming)
  /// Intervals given but left out of the final fit: the robust screening's outliers plus, for
  /// joint, the closed form's fixed-fraction rounds (JointParams::trim_fraction).
  int intervals_trimmed = 0;
  /// The screening's worst outliers (up to TrimParams::report_worst), worst first.
  std::vector<TrimmedInterval> trimmed_worst;
  /// The rotation step's test for residuals that grow with the turn (turnHeteroscedasticity;
  /// model, joint, ceres through joint; 0 for the others).
  double rotation_heteroscedasticity = 0.0;
  /// Per parameter of `covariance`, its sigma over the model's where the sandwich raised it
  /// (sandwichFloor; >= 1); empty where no sandwich was taken (heading loops, direct, umbmark).
  std::vector<double> sigma_sandwich_factors;
  int iterations = 0;  ///< solver iterations or trimming rounds
  double cost = 0.0;   ///< final sum of squared (weighted) residuals

  /// 1-sigma of each estimated parameter (sqrt of the covariance diagonal), zeros if unknown.
  Eigen::VectorXd sigma() const;
};

/// The parameter keys, in the order of the JSON, the `calibrate` table and the covariance.
inline constexpr std::array<const char*, 6> kCalibrationKeys = {"r_L",     "r_R",     "b",
                                                                "lidar_x", "lidar_y", "lidar_yaw"};

/// r_L, r_R, b and, when the result estimates the mount, lidar_x, lidar_y, lidar_yaw.
Eigen::VectorXd calibrationValues(const CalibrationResult& result);

/// Condition number sigma_max / sigma_min of A after scaling every column to unit norm (units
/// and scale of the unknowns then do not matter). +inf when a column is zero or rank deficient.
double equilibratedConditionNumber(const Eigen::MatrixXd& A);

/// Whether the rotation residuals grow with the turn (slip in turns: the wheels count (1 + u) of
/// the turn they made): Koenker's Breusch-Pagan statistic n R^2 of the squared residuals
/// regressed on the squared predicted rotations, chi^2 with one degree of freedom where the
/// variance does not depend on the turn (over kTurnHeteroscedasticityMinStatistic: it does).
/// A finding to report; the sigmas allow for it through the sandwich (sandwichFloor).
double turnHeteroscedasticity(const Eigen::VectorXd& residual, const Eigen::VectorXd& predicted);

/// Stage 1 of the model-based and joint methods: theta_k = J21 sum dphi_L + J22 sum dphi_R.
struct RotationFit {
  bool ok = false;
  std::string reason;
  double J21 = 0.0;  ///< -r_L / b
  double J22 = 0.0;  ///< r_R / b
  /// of (J21, J22): sigma_theta^2 (A^T A)^-1 times adjacentCorrelationFactor of the residuals
  Eigen::Matrix2d covariance = Eigen::Matrix2d::Zero();
  double turn_heteroscedasticity = 0.0;  ///< turnHeteroscedasticity of the residuals
  double sigma_theta_rad = 0.0;          ///< rotation noise estimated from the residuals
  double condition_number = 0.0;         ///< of the n x 2 design [sum dphi_L, sum dphi_R]
  std::vector<double> residuals_rad;     ///< measured minus predicted rotation, per interval
};

/// Long-run variance factor 1 + 2 rho of one residual per interval: rho is the correlation of
/// the residuals of intervals that meet end to start (one scan shared by two consecutive scan
/// matches enters them with opposite signs, so rho < 0 and errors partly cancel along a chain).
/// Multiplying a per-interval variance by it gives the variance of a sum over many consecutive
/// intervals (docs/design.md, "Calibration: is the reported sigma honest?"). rho is clamped to
/// [-0.45, 0.5] (an MA(1) process has |rho| <= 0.5); 1 when no two intervals meet.
double adjacentCorrelationFactor(const std::vector<CalibrationInterval>& intervals,
                                 const std::vector<double>& residuals);

/// Least-squares rotation fit (docs/design.md, "Calibration: model-based method", step 1).
/// Refuses (with the reason naming the kind of driving) when the design is worse conditioned
/// than max_condition, and detects swapped or sign-flipped encoder channels from the signs of
/// J21 and J22.
/// `heading_loops`: spans whose headings loop closures corrected; the covariance propagates the
/// correction (loop_covariance.hpp).
RotationFit fitRotation(const std::vector<CalibrationInterval>& intervals, double max_condition,
                        const std::vector<LoopSpan>& heading_loops = {});

/// Heading and unit-b translation of an interval given J21, J22: the odometry displacement is
/// exactly b * c with c = sum_j R(theta_j) (sinc dth_j, cosc dth_j) (-J21 dphi_L + J22 dphi_R)/2
/// (exact arcs over the encoder steps), and the rotation o_th = sum_j dth_j. A sideslip k
/// (motion_model.hpp) adds m * d with m = k b, d = sum_j R(theta_j) (-cosc dth_j, sinc dth_j)
/// ds_j dth_j / dt_j, ds_j the step's distance per unit b: also linear in the unknown.
struct UnitOdometry {
  Eigen::Vector2d c = Eigen::Vector2d::Zero();
  Eigen::Vector2d d = Eigen::Vector2d::Zero();
  double o_th = 0.0;
};
UnitOdometry unitOdometry(const CalibrationInterval& interval, double J21, double J22);

/// Names the kind of driving that leaves the wheel rotations of every interval proportional.
std::string describeDegenerateDriving(const std::vector<CalibrationInterval>& intervals);

/// Covariance of (p1, p2) for a two-stage estimator: p1 = (J21, J22) with covariance cov1, then p2
/// minimising sum_k |e_k(p2; p1)|^2 with G_k = de_k/dp2, F_k = de_k/dp1. First order:
///   dp2 = -H^-1 sum_k G_k^T (F_k dp1 + n_k),  H = sum_k G_k^T G_k,
///   cov(p2) = H^-1 N H^-1 + K cov1 K^T,  N = sum_k G_k^T cov(n_k) G_k,  K = -H^-1 sum G_k^T F_k,
///   cov(p2, p1) = K cov1  (stage-1 and stage-2 noise are independent: rotation vs translation).
Eigen::MatrixXd twoStageCovariance(const Eigen::Matrix2d& cov1, const Eigen::MatrixXd& H,
                                   const Eigen::MatrixXd& N, const Eigen::MatrixXd& sumGtF);

/// Newey-West with one lag over intervals: sum_k v_k v_k^T, plus v_k v_{k+1}^T + v_{k+1} v_k^T
/// where interval k ends as k + 1 starts (their errors share a scan), times n / (n - estimated),
/// HC1's small-sample factor. v_k is interval k's contribution to an estimator's score or error.
Eigen::MatrixXd intervalOuterSum(const std::vector<CalibrationInterval>& intervals,
                                 const std::vector<Eigen::VectorXd>& v, Eigen::Index estimated);

/// The sandwich covariance of the two-stage estimator of twoStageCovariance, with each
/// interval's residuals standing for its noise (Eq. S1):
///   dp1_k = (A^T A)^-1 a_k r_k,   a_k = (sum dphi_L, sum dphi_R), r_k its rotation residual,
///   dp2_k = -H^-1 G_k^T e_k + K dp1_k,   (S1)
/// summed by intervalOuterSum over d_k = (dp1_k, dp2_k). Unlike twoStageCovariance it holds
/// whatever each interval's noise variance (slip in turns, longer intervals) and whether rotation
/// and translation noise correlate; `e` stacks the e_k, `G` the G_k (2 rows each).
Eigen::MatrixXd twoStageSandwich(const std::vector<CalibrationInterval>& intervals,
                                 const std::vector<double>& rotation_residuals,
                                 const Eigen::MatrixXd& G, const Eigen::VectorXd& e,
                                 const Eigen::MatrixXd& sumGtF);

/// A covariance at least `model` and at least `sandwich` in every direction: in the model's
/// whitened coordinates, the sandwich's eigenvalues below 1 raised to 1 (where the sandwich is
/// smaller, the model stands). Model-based sigmas assume one noise level for every interval and
/// understate a parameter that the noisier intervals decide: on the twins of real recordings b's
/// error over its sigma had a mean square of 2.3 without the floor, 1.4 with it (docs/design.md
/// "Slip in turns, and noise that differs between intervals"). `factors` gets each parameter's
/// sigma over the model's (>= 1).
Eigen::MatrixXd sandwichFloor(const Eigen::MatrixXd& model, const Eigen::MatrixXd& sandwich,
                              std::vector<double>& factors);

/// Maps a covariance over (J21, J22, b, rest...) to (r_L, r_R, b, rest...) with r_L = -J21 b,
/// r_R = J22 b (first-order, the Jacobian of that map).
Eigen::MatrixXd radiiCovariance(const Eigen::MatrixXd& cov_J, double J21, double J22, double b);

/// Smallest number of intervals below which every method refuses.
inline constexpr int kMinIntervalsAbsolute = 3;

}  // namespace slamprep::algo
