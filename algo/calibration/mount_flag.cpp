#include "slamprep/algo/calibration/mount_flag.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

namespace slamprep::algo {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

// sqrt of the largest eigenvalue of the (lidar_x, lidar_y) covariance: the loosest direction.
double sigmaOffset(const CalibrationResult& r) {
  if (r.covariance.rows() < 6) return 0.0;
  const Eigen::Matrix2d c = r.covariance.block<2, 2>(3, 3);
  const double mean = 0.5 * c.trace();
  const double half_gap =
      std::sqrt(0.25 * (c(0, 0) - c(1, 1)) * (c(0, 0) - c(1, 1)) + c(0, 1) * c(0, 1));
  return std::sqrt(std::max(0.0, mean + half_gap));
}

double sigmaYaw(const CalibrationResult& r) {
  return r.covariance.rows() < 6 ? 0.0 : std::sqrt(std::max(0.0, r.covariance(5, 5)));
}

}  // namespace

std::optional<NominalFlag> mountFlag(const CalibrationResult& result, const SE2& given,
                                     const std::string& given_from, const MountFlagParams& p) {
  if (!result.ok || !result.estimates_mount) return std::nullopt;
  const SE2& m = result.T_base_lidar;
  const double offset = std::hypot(m.x - given.x, m.y - given.y);
  const double yaw = std::abs(std::remainder(m.yaw - given.yaw, 2.0 * std::numbers::pi));
  if (offset <= p.max_offset_m && yaw <= p.max_yaw_deg * kRadPerDeg) return std::nullopt;
  // Excluded: a part beyond its limit that the estimate's own sigma does not reach either.
  const bool excluded = (offset > p.max_offset_m && offset > p.sigmas * sigmaOffset(result)) ||
                        (yaw > p.max_yaw_deg * kRadPerDeg && yaw > p.sigmas * sigmaYaw(result));
  char text[480];
  std::snprintf(text, sizeof text,
                "the calibrated lidar mount is %.0f mm and %.1f deg from the dataset's (%s; "
                "sigma %.0f mm, %.1f deg): %s",
                offset * 1e3, yaw / kRadPerDeg, given_from.c_str(), sigmaOffset(result) * 1e3,
                sigmaYaw(result) / kRadPerDeg,
                excluded ? "either that mount is wrong or the fit absorbed an error of the wheels "
                           "or clocks into the mount (slip, a lag, a drifting matched heading); "
                           "the wheel geometry of this fit is suspect with it"
                         : "the recording does not pin the mount down (too little turning); "
                           "keep the dataset's mount (--lidar-mount dataset)");
  return NominalFlag{"lidar_mount", 1.0, text};
}

}  // namespace slamprep::algo
