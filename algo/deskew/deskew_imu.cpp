// IMU-assisted de-skew: the rotation over the scan from the gyro's yaw rate, integrated at the
// IMU's own rate (trapezoid between samples, linear at the scan's ends),
//   dtheta_k = (w_{k-1} + w_k) / 2 (t_k - t_{k-1}),
// the translation from the odometry's own twist rho_odom over the same interval:
//   T_base0_base(t_k) = T_base0_base(t_{k-1}) exp(rho_odom, dtheta_k),
// and T_X_L(t_k) = T_base0_base(t_k) T_base_lidar.
#include <algorithm>

#include "slamprep/algo/deskew/method.hpp"

namespace slamprep::algo {
namespace {

/// (stamp, yaw rate) at the scan's first beam, at every IMU sample inside, and at its last beam;
/// refuses when the IMU does not bracket the scan or has a gap inside it.
std::vector<std::pair<double, double>> gyroSamples(const ImuLog& imu, const ScanTimes& t,
                                                   double max_gap_s) {
  auto later = [](double s, const ImuSample& x) { return s < x.stamp_s; };
  const auto after_first = std::upper_bound(imu.begin(), imu.end(), t.first_s, later);
  const auto after_last = std::upper_bound(imu.begin(), imu.end(), t.last_s, later);
  if (imu.empty() || after_first == imu.begin() || after_last == imu.end())
    throw Refusal{DeskewRefusal::kNotBracketed, "IMU does not bracket the scan [" + fmt(t.first_s) +
                                                    ", " + fmt(t.last_s) + "] s"};
  for (auto it = after_first - 1; it != after_last; ++it)
    if ((it + 1)->stamp_s - it->stamp_s > max_gap_s)
      throw Refusal{DeskewRefusal::kSampleGap,
                    "IMU has a gap of " + fmt((it + 1)->stamp_s - it->stamp_s) + " s at t = " +
                        fmt(it->stamp_s) + " inside the scan; refused, not integrated across"};
  auto gyroAt = [&](std::vector<ImuSample>::const_iterator hi, double s) {  // linear
    const auto lo = hi - 1;
    const double f = (s - lo->stamp_s) / (hi->stamp_s - lo->stamp_s);
    return lo->gyro_z_radps + f * (hi->gyro_z_radps - lo->gyro_z_radps);
  };
  std::vector<std::pair<double, double>> samples;
  samples.emplace_back(t.first_s, gyroAt(after_first, t.first_s));
  for (auto it = after_first; it != after_last; ++it)
    if (it->stamp_s > t.first_s) samples.emplace_back(it->stamp_s, it->gyro_z_radps);
  if (t.last_s > samples.back().first) samples.emplace_back(t.last_s, gyroAt(after_last, t.last_s));
  return samples;
}

}  // namespace

Trajectory imuKnots(const MethodCall& call) {
  // The odometry samples around the scan (base frame), checked for bracketing and gaps.
  const Trajectory T_odom_base = lidarKnots(call, call.in.odometry, SE2(), "odometry");
  const auto samples = gyroSamples(call.in.imu, call.t, call.params.max_sample_gap_s);
  const SE2& T_base_lidar = call.in.T_base_lidar;
  Trajectory knots;
  knots.reserve(samples.size());
  SE2 T_base0_base;
  SE2 T_odom_prev = poseAt(T_odom_base, samples[0].first);
  knots.push_back({samples[0].first, T_base0_base * T_base_lidar});
  for (std::size_t k = 1; k < samples.size(); ++k) {
    const SE2 T_odom_cur = poseAt(T_odom_base, samples[k].first);
    const Eigen::Vector3d rho = between(T_odom_prev, T_odom_cur).log();
    const double dtheta = 0.5 * (samples[k - 1].second + samples[k].second) *
                          (samples[k].first - samples[k - 1].first);
    T_base0_base = T_base0_base * SE2::exp({rho.x(), rho.y(), dtheta});
    knots.push_back({samples[k].first, T_base0_base * T_base_lidar});
    T_odom_prev = T_odom_cur;
  }
  return relativeTo(knots, call.t.ref_s);
}

}  // namespace slamprep::algo
