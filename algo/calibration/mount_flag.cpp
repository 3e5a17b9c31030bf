#include "slamprep/algo/calibration/mount_flag.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>

namespace slamprep::algo {
namespace {

constexpr double kRadPerDeg = std::numbers::pi / 180.0;

// 1-sigma of the mount's offset in its loosest direction (the largest eigenvalue of the
// (lidar_x, lidar_y) covariance) and of its yaw; zeros without a 6x6 covariance.
std::pair<double, double> mountSigmas(const CalibrationResult& r) {
  if (r.covariance.rows() < 6) return {0.0, 0.0};
  const Eigen::Matrix2d c = r.covariance.block<2, 2>(3, 3);
  const double loosest = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(c).eigenvalues()(1);
  return {std::sqrt(std::max(0.0, loosest)), std::sqrt(std::max(0.0, r.covariance(5, 5)))};
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
  const auto [sigma_offset, sigma_yaw] = mountSigmas(result);
  const bool excluded = (offset > p.max_offset_m && offset > p.sigmas * sigma_offset) ||
                        (yaw > p.max_yaw_deg * kRadPerDeg && yaw > p.sigmas * sigma_yaw);
  char text[480];
  std::snprintf(text, sizeof text,
                "the calibrated lidar mount is %.0f mm and %.1f deg from the dataset's (%s; "
                "sigma %.0f mm, %.1f deg): %s",
                offset * 1e3, yaw / kRadPerDeg, given_from.c_str(), sigma_offset * 1e3,
                sigma_yaw / kRadPerDeg,
                excluded ? "either that mount is wrong or the fit absorbed an error of the wheels "
                           "or clocks into the mount (slip, a lag, a drifting matched heading); "
                           "the wheel geometry of this fit is suspect with it"
                         : "the recording does not pin the mount down (too little turning); "
                           "keep the dataset's mount (--lidar-mount dataset)");
  return NominalFlag{"lidar_mount", 1.0, text};
}

}  // namespace slamprep::algo
