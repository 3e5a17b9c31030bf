#include "slamprep/core/heading.hpp"

#include <cmath>

namespace slamprep {

HeadingSeries gyroHeading(const ImuLog& imu) {
  HeadingSeries heading;
  heading.reserve(imu.size());
  double yaw = 0.0;
  for (std::size_t k = 0; k < imu.size(); ++k) {
    if (k > 0)
      yaw += 0.5 * (imu[k - 1].gyro_z_radps + imu[k].gyro_z_radps) *
             (imu[k].stamp_s - imu[k - 1].stamp_s);
    heading.push_back(imu[k].stamp_s, yaw);
  }
  return heading;
}

HeadingSeries poseHeading(const PoseSeries& poses) {
  HeadingSeries heading;
  heading.reserve(poses.size());
  double yaw = poses.empty() ? 0.0 : poses[0].value.yaw;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    if (k > 0) yaw += normalizeAngle(poses[k].value.yaw - poses[k - 1].value.yaw);
    heading.push_back(poses[k].stamp_s, yaw);
  }
  return heading;
}

TimeSeries<double> poseTravel(const PoseSeries& poses) {
  TimeSeries<double> travel;
  travel.reserve(poses.size());
  double s = 0.0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    if (k > 0) {
      const SE2& a = poses[k - 1].value;
      const SE2& b = poses[k].value;
      const double yaw = a.yaw + 0.5 * normalizeAngle(b.yaw - a.yaw);
      s += (b.x - a.x) * std::cos(yaw) + (b.y - a.y) * std::sin(yaw);
    }
    travel.push_back(poses[k].stamp_s, s);
  }
  return travel;
}

std::optional<double> turned(const HeadingSeries& heading, double t0_s, double t1_s,
                             double max_gap_s) {
  const auto b0 = heading.bracket(t0_s), b1 = heading.bracket(t1_s);
  if (!b0 || !b1) return std::nullopt;
  // Every sample interval that overlaps (t0, t1) must be short (any is, under no limit).
  if (std::isfinite(max_gap_s))
    for (std::size_t k = b0->index; k + 1 < heading.size() && heading[k].stamp_s < t1_s; ++k)
      if (heading[k + 1].stamp_s - heading[k].stamp_s > max_gap_s) return std::nullopt;
  return *heading.at(t1_s) - *heading.at(t0_s);
}

}  // namespace slamprep
