#include "sim/physics/lidar.hpp"

#include <cmath>

namespace slamprep::sim {

Lidar::Lidar(const LidarConfig& config, std::uint64_t seed) : config_(config), rng_(seed) {
  beams_per_scan_ = static_cast<std::size_t>(
      std::lround(config.beams_per_revolution * config.fov_rad / (2 * std::numbers::pi)));
}

LaserScan Lidar::header(double stamp_s) const {
  LaserScan scan;
  scan.stamp_s = stamp_s;
  scan.ranges_m.assign(beams_per_scan_, std::numeric_limits<double>::infinity());
  return scan;
}

Lidar::Beam Lidar::measure(const Scene&, const SE2&, std::size_t) {
  const double inf = std::numeric_limits<double>::infinity();
  return {inf, inf};
}

double Lidar::gaussian() {
  return 0.0;
}

}  // namespace slamprep::sim
