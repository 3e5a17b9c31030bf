#pragma once
// Wheels and a wheel base all off the nominal by one factor (docs/calibration.md, "Flags"): what
// a lidar whose ranges read that much long or short gives. Scan-matched translation scales with
// the ranges and rotation does not, so a calibration from scans and wheels scales r_L, r_R and,
// to keep the turn per wheel angle r / b, b by the range scale; no comparison of scans, wheels
// or gyro tells that from wheels that large. The Freiburg hospital's laser reads 1.4 % long.

#include <optional>

#include "slamprep/algo/calibration/calibration_result.hpp"
#include "slamprep/algo/calibration/nominal_flags.hpp"
#include "slamprep/core/diff_drive.hpp"

namespace slamprep::algo {

struct ScaleFlagParams {
  double sigmas = 3.0;  ///< the common factor is this many of its sigmas from 1
  /// The three ratios agree with one factor: their generalised chi2 about it (2 degrees of
  /// freedom) under this (chi2(2) at p = 0.001).
  double max_chi2 = 13.82;
};

/// The common factor of q = (r_L, r_R, b) / nominal and how well one factor explains them, by
/// generalised least squares with the estimate's covariance C_q:
///   s = 1' C_q^-1 q / 1' C_q^-1 1,  sigma_s^2 = 1 / 1' C_q^-1 1,                      (Eq. 1)
///   chi2 = (q - s 1)' C_q^-1 (q - s 1).                                                (Eq. 2)
struct CommonScale {
  double factor = 1.0;
  double sigma = 0.0;
  double chi2 = 0.0;
};

/// nullopt where the result is not ok or has no usable covariance.
std::optional<CommonScale> commonScale(const CalibrationResult& result,
                                       const DiffDriveParams& nominal);

/// A flag with param "range_scale" (ratio s) where one factor explains r_L, r_R and b (chi2
/// under max_chi2) and lies beyond `sigmas` of its sigma from 1: the cause names the lidar's
/// range scale beside a nominal geometry wrong by that factor, and how to tell them apart.
std::optional<NominalFlag> scaleFlag(const CalibrationResult& result,
                                     const DiffDriveParams& nominal,
                                     const ScaleFlagParams& params = {});

}  // namespace slamprep::algo
