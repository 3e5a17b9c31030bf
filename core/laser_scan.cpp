#include "slamprep/core/laser_scan.hpp"

#include <cmath>
#include <numbers>

#include "slamprep/core/se2.hpp"

namespace slamprep {

Eigen::Vector2d LaserScan::point(std::size_t i) const {
  const double a = beamAngle(i);
  return ranges_m[i] * Eigen::Vector2d(std::cos(a), std::sin(a));
}

Points2 LaserScan::points() const {
  Points2 out;
  out.reserve(size());
  for (std::size_t i = 0; i < size(); ++i)
    if (valid(i)) out.push_back(point(i));
  return out;
}

LaserScan repackPoints(const LaserScan& grid,
                       const std::vector<std::optional<Eigen::Vector2d>>& p_lidar) {
  LaserScan out = grid;
  const double inf = std::numeric_limits<double>::infinity();
  out.ranges_m.assign(grid.size(), inf);
  if (grid.size() == 0 || grid.angle_increment_rad == 0.0) return out;
  for (const auto& p : p_lidar) {
    if (!p) continue;
    const double range = p->norm();
    // Offset from angle_min, wrapped so a full revolution maps back onto the grid.
    const double offset = normalizeAngle(std::atan2(p->y(), p->x()) - grid.angle_min_rad);
    double k = offset / grid.angle_increment_rad;
    if (k < -0.5) k += 2.0 * std::numbers::pi / std::abs(grid.angle_increment_rad);
    const long bin = std::lround(k);
    if (bin < 0 || bin >= static_cast<long>(grid.size())) continue;
    out.ranges_m[bin] = std::min(out.ranges_m[bin], range);
  }
  return out;
}

}  // namespace slamprep
