#include "slamprep/algo/calibration/robust_trim.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "slamprep/core/order_statistics.hpp"

namespace slamprep::algo {
namespace {

// Eq. (1): median and MAD-based sigma of one residual component.
std::pair<double, double> robustScale(const std::vector<Eigen::Vector3d>& r, int c, double floor) {
  std::vector<double> v;
  v.reserve(r.size());
  for (const auto& rk : r) v.push_back(rk(c));
  const double m = median(v);
  for (double& x : v) x = std::abs(x - m);
  return {m, std::max(1.4826 * median(std::move(v)), floor)};
}

std::string describe(int c, double residual) {
  char text[96];
  if (c == 2)
    std::snprintf(text, sizeof text, "rotation disagrees by %.3g deg",
                  residual * 180.0 / std::numbers::pi);
  else
    std::snprintf(text, sizeof text, "translation %s disagrees by %.3g m", c == 0 ? "x" : "y",
                  residual);
  return text;
}

}  // namespace

std::vector<Eigen::Vector3d> intervalResiduals(const std::vector<CalibrationInterval>& intervals,
                                               const DiffDriveParams& geometry,
                                               const SE2& T_base_lidar) {
  std::vector<Eigen::Vector3d> r;
  r.reserve(intervals.size());
  const SE2 T_lidar_base = T_base_lidar.inverse();
  for (const CalibrationInterval& interval : intervals) {
    const SE2 p = T_lidar_base * integrateInterval(interval, geometry) * T_base_lidar;
    const SE2& s = interval.T_lidarStart_lidarEnd;
    r.emplace_back(s.x - p.x, s.y - p.y, normalizeAngle(s.yaw - p.yaw));
  }
  return r;
}

Screening screenIntervals(const std::vector<CalibrationInterval>& intervals,
                          const CalibrationResult& fit, const TrimParams& params) {
  Screening out;
  const auto r = intervalResiduals(intervals, fit.geometry, fit.T_base_lidar);
  if (r.empty()) return out;
  std::pair<double, double> scale[3];
  for (int c = 0; c < 3; ++c)
    scale[c] = robustScale(r, c, c == 2 ? params.min_sigma_rad : params.min_sigma_m);
  for (std::size_t k = 0; k < r.size(); ++k) {
    int worst = 0;
    double z = 0.0;
    for (int c = 0; c < 3; ++c) {  // Eq. (2)
      const double zc = std::abs(r[k](c) - scale[c].first) / scale[c].second;
      if (zc > z) {
        z = zc;
        worst = c;
      }
    }
    if (z > params.threshold_sigmas)
      out.dropped.push_back({intervals[k].t_start_s, intervals[k].t_end_s,
                             describe(worst, r[k](worst) - scale[worst].first), z});
    else
      out.kept.push_back(static_cast<int>(k));
  }
  std::stable_sort(out.dropped.begin(), out.dropped.end(),
                   [](const TrimmedInterval& a, const TrimmedInterval& b) {
                     return a.residual_sigmas > b.residual_sigmas;
                   });
  return out;
}

std::vector<CalibrationInterval> selectIntervals(const std::vector<CalibrationInterval>& all,
                                                 const std::vector<int>& indices) {
  std::vector<CalibrationInterval> out;
  out.reserve(indices.size());
  for (int i : indices) out.push_back(all[static_cast<std::size_t>(i)]);
  return out;
}

}  // namespace slamprep::algo
