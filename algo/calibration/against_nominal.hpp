#pragma once
// Does the recording show the nominal geometry is wrong? (docs/calibration.md, "Against the
// nominal".) A calibrated geometry within its own uncertainty of the nominal one moves the
// odometry by noise: on held-out driving it predicts no better than the nominal, and half the
// time worse. The test reads that from the estimate's covariance, so it is as honest as the
// sigmas are (on short real recordings it did not predict their held-out parts).

#include <Eigen/Core>
#include <optional>

#include "slamprep/algo/calibration/calibration_result.hpp"
#include "slamprep/core/diff_drive.hpp"

namespace slamprep::algo {

struct NominalTestParams {
  /// The nominal is shown wrong at p below this (chi2 with 3 degrees of freedom over 16.27).
  double alpha = 0.001;
};

/// The estimate g = (r_L, r_R, b) against the nominal n with the estimate's covariance C:
///   chi2 = (g - n)' C^-1 (g - n),   3 degrees of freedom,                            (Eq. 1)
///   p    = P(chi2_3 > chi2) = erfc(sqrt(chi2 / 2)) + sqrt(2 chi2 / pi) exp(-chi2 / 2), (Eq. 2)
///   z_i  = (g_i - n_i) / sqrt(C_ii)   (each parameter alone).
struct NominalTest {
  double chi2 = 0.0;
  int dof = 3;
  double p = 1.0;
  Eigen::Vector3d z = Eigen::Vector3d::Zero();  ///< r_L, r_R, b
  bool shows_nominal_wrong = false;             ///< p < alpha
};

/// P(chi2 with 3 degrees of freedom > x), Eq. 2; 1 for x <= 0.
double chi2Survival3(double x);

/// nullopt where the result is not ok or its covariance of (r_L, r_R, b) is not positive
/// definite.
std::optional<NominalTest> nominalTest(const CalibrationResult& result,
                                       const DiffDriveParams& nominal,
                                       const NominalTestParams& params = {});

}  // namespace slamprep::algo
