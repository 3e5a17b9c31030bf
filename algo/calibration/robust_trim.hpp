#pragma once
// Robust screening of calibration intervals (docs/calibration.md, "Robust trimming"): intervals
// whose measured lidar motion disagrees with a first fit by far more than the rest are dropped
// and the fit repeated, until the set of kept intervals no longer changes.
//
// Residual of interval k against a fit (geometry g, mount l):
//   r_k = (s_x - p_x, s_y - p_y, wrap(s_th - p_th)),  p = l^-1 o_k(g) l,  s = measured motion.
// Robust scale per component c (the MAD, 50 % breakdown):
//   m_c = median_k r_kc,  sigma_c = max(1.4826 median_k |r_kc - m_c|, sigma_floor_c),     (Eq. 1)
// (1.4826 makes the MAD a consistent estimate of a Gaussian's sigma). Robust score:
//   z_k = max_c |r_kc - m_c| / sigma_c.                                                  (Eq. 2)
// An interval is an outlier when z_k > threshold. Median and MAD are taken over all intervals
// in every round, so the glitches cannot inflate the scale that judges them.

#include <string>
#include <vector>

#include "slamprep/algo/calibration/calibration_result.hpp"

namespace slamprep::algo {

struct TrimParams {
  bool enabled = true;
  /// z above which an interval is dropped. 5: a Gaussian residual exceeds it with probability
  /// 6e-7 per component, so clean data loses nothing; odometry glitches score in the hundreds.
  double threshold_sigmas = 5.0;
  /// Fit / screen rounds at most (stops earlier once the kept set repeats).
  int max_rounds = 5;
  /// How many of the dropped intervals the result lists (worst first).
  int report_worst = 5;
  /// Floors of the robust sigma (noise-free synthetic data has MAD ~ 1e-16).
  double min_sigma_m = 1e-4;
  double min_sigma_rad = 1e-4;
};

/// Measured minus predicted lidar motion of each interval, (x m, y m, theta rad).
std::vector<Eigen::Vector3d> intervalResiduals(const std::vector<CalibrationInterval>& intervals,
                                               const DiffDriveParams& geometry,
                                               const SE2& T_base_lidar);

/// The kept intervals and the dropped ones (worst first, all of them).
struct Screening {
  std::vector<int> kept;                 ///< indices into the screened intervals, ascending
  std::vector<TrimmedInterval> dropped;  ///< z > threshold, sorted by z descending
};

/// Eqs. (1)-(2) on the residuals of `intervals` against `fit` (its geometry and mount).
Screening screenIntervals(const std::vector<CalibrationInterval>& intervals,
                          const CalibrationResult& fit, const TrimParams& params);

/// The intervals at `indices`.
std::vector<CalibrationInterval> selectIntervals(const std::vector<CalibrationInterval>& all,
                                                 const std::vector<int>& indices);

}  // namespace slamprep::algo
