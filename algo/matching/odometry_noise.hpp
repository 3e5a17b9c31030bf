#pragma once
// The odometry's noise per scan step, measured on the recording (docs/matching.md "Odometry
// noise"): what the fusion of a match with the odometry guess weighs the odometry by.
//
// The scans are tracked once with the fusion off. For an accepted scan k with an odometry step,
// the step's disagreement with the scans is
//   d_k = (T_world_{k-1} odom_k)^-1 T_world_k = odometry error + match error.        (Eq. 1)
// Its spread bounds the odometry's noise from above. Where the map explains a scan well the match
// error is smallest, so only the scans whose support is at least the median support are used:
//   sigma_rad = 1.4826 median |d_yaw|                 (Gaussian sigma from the MAD),  (Eq. 2)
//   sigma_m   = median |d_xy| / 1.1774                (an isotropic 2D Gaussian's |d|
//                                                      has the Rayleigh median 1.1774 sigma). (Eq.
//                                                      3)
// A robot whose odometry is better than its scans (a gyro-aided base outdoors, where the map
// is bushes and posts) is then followed closely; one whose odometry slips is not.

#include <cstddef>
#include <optional>
#include <vector>

#include "slamprep/algo/matching/keyframe_odometry.hpp"

namespace slamprep::algo {

struct OdometryNoise {
  double sigma_m = 0.0;      ///< translation per scan step, 1 sigma (Eq. 3)
  double sigma_rad = 0.0;    ///< heading per scan step, 1 sigma (Eq. 2)
  std::size_t steps = 0;     ///< steps it was measured on
  double min_support = 0.0;  ///< the support those scans had at least (the median)
};

/// Fewer steps than this measure nothing: the given noise is kept.
inline constexpr std::size_t kMinOdometryNoiseSteps = 30;

/// The least noise measured: 0.1 mm and 0.001 degree per step (0 would turn the fusion off).
inline constexpr double kMinOdometrySigmaM = 1e-4;
inline constexpr double kMinOdometrySigmaRad = 1.7453292519943295e-5;

/// Eqs. 1-3 from `scans_alone` (trackKeyframes with odometry_sigma 0) and the `priors` it was
/// tracked with. nullopt where fewer than kMinOdometryNoiseSteps steps qualify.
std::optional<OdometryNoise> measureOdometryNoise(const KeyframeOdometry& scans_alone,
                                                  const std::vector<StepPrior>& priors);

}  // namespace slamprep::algo
