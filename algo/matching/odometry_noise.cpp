#include "slamprep/algo/matching/odometry_noise.hpp"

#include <algorithm>
#include <cmath>

#include "slamprep/core/order_statistics.hpp"

namespace slamprep::algo {
namespace {

/// One step's disagreement (Eq. 1) and the support of the scan it ends at.
struct StepDisagreement {
  SE2 d;
  double support = 0.0;
};

std::vector<StepDisagreement> disagreements(const KeyframeOdometry& scans_alone,
                                            const std::vector<StepPrior>& priors) {
  std::vector<StepDisagreement> out;
  const auto& scans = scans_alone.scans;
  for (std::size_t k = 1; k < scans.size() && k < priors.size(); ++k) {
    if (scans[k].fallback || !priors[k].odometry) continue;
    const SE2 T_world_odometry = scans[k - 1].T_world_lidar * *priors[k].odometry;
    out.push_back({between(T_world_odometry, scans[k].T_world_lidar), scans[k].support.fraction()});
  }
  return out;
}

}  // namespace

std::optional<OdometryNoise> measureOdometryNoise(const KeyframeOdometry& scans_alone,
                                                  const std::vector<StepPrior>& priors) {
  const std::vector<StepDisagreement> steps = disagreements(scans_alone, priors);
  if (steps.size() < kMinOdometryNoiseSteps) return std::nullopt;
  std::vector<double> supports;
  for (const auto& s : steps) supports.push_back(s.support);
  const double min_support = median(supports);
  std::vector<double> yaw, xy;
  for (const auto& s : steps) {
    if (s.support < min_support) continue;
    yaw.push_back(std::abs(s.d.yaw));
    xy.push_back(s.d.translation().norm());
  }
  if (yaw.size() < kMinOdometryNoiseSteps) return std::nullopt;
  OdometryNoise noise;
  // Never exactly 0, which would turn the fusion off: a resolution, not a noise.
  noise.sigma_rad = std::max(1.4826 * median(yaw), kMinOdometrySigmaRad);        // Eq. 2
  noise.sigma_m = std::max(median(std::move(xy)) / 1.1774, kMinOdometrySigmaM);  // Eq. 3
  noise.steps = yaw.size();
  noise.min_support = min_support;
  return noise;
}

}  // namespace slamprep::algo
