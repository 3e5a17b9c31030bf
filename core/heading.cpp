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

}  // namespace slamprep
