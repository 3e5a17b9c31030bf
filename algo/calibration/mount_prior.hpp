#pragma once
// The lidar mount a recording comes with (a tf, --lidar-mount) as a prior on the mount that
// joint and ceres estimate (docs/calibration.md, "Mount prior"). A short drive with little
// turning leaves the mount loose, and a loose mount takes the wheel base with it through their
// correlation: on short real Neato recordings the calibrated wheels with the tf mount predicted
// held-out driving better than the joint fit's own wheels and mount. The prior is fused as one
// more measurement of the mount (a linear Gaussian update of the fit, which also moves the
// wheels by their correlation with the mount); a fit that contradicts it is left alone.
//
//   z = m + n,  n ~ N(0, R),  R = diag(s_xy^2, s_xy^2, s_yaw^2),  H = [0 I_3]      (1)
//   nu = z - H x (yaw wrapped),  S = H P H^T + R,  chi2 = nu^T S^-1 nu            (2)
//   K = P H^T S^-1,  x+ = x + K nu,  P+ = (I - K H) P (I - K H)^T + K R K^T        (3)
//
// x = (r_L, r_R, b, l_x, l_y, l_yaw) and P are the fit's estimate and covariance; (3) is the
// minimiser of (x - x0)^T P^-1 (x - x0) + (H x - z)^T R^-1 (H x - z) and its inverse Hessian.

#include <Eigen/Core>
#include <optional>
#include <string>

#include "slamprep/algo/calibration/calibration_result.hpp"
#include "slamprep/core/se2.hpp"

namespace slamprep::algo {

/// The mount given with a recording and how far it is trusted.
struct MountPrior {
  SE2 T_base_lidar;
  std::string from;              ///< where it was measured ("tf base_link -> laser")
  double sigma_xy_m = 0.02;      ///< a URDF mount is measured on the robot to a centimetre or two
  double sigma_yaw_rad = 0.035;  ///< 2 deg
  /// Eq. (2) beyond this: the fit contradicts the prior and is left alone (chi2, 3 degrees of
  /// freedom, 0.27 % above it: the 3-sigma level), and the mount flag says so.
  double max_chi2 = 14.16;
};

/// What the prior did to one fit (the JSON's "mount_prior").
struct MountPriorUse {
  MountPrior prior;
  double chi2 = 0.0;     ///< Eq. (2)
  bool applied = false;  ///< false: chi2 > max_chi2, the fit kept as it was
  /// The fit before the prior (r_L, r_R, b, l_x, l_y, l_yaw) and its 1-sigmas.
  Eigen::VectorXd without_prior, without_prior_sigma;
};

/// Fuses `prior` into an ok result that estimates the mount and has its 6x6 covariance
/// (Eq. 1-3); nullopt, the result untouched, for any other.
std::optional<MountPriorUse> applyMountPrior(CalibrationResult& result, const MountPrior& prior);

}  // namespace slamprep::algo
