#pragma once
// LaserScan in the ROS sensor_msgs/LaserScan convention (docs/design.md#time-stamps).

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

namespace slamprep {

using Points2 = std::vector<Eigen::Vector2d>;

/// One revolution of a rotating 2D lidar. Beam i is at angle angle_min + i * angle_increment,
/// taken at stamp + i * time_increment. A beam with no return holds +inf (REP 117).
struct LaserScan {
  double stamp_s = 0.0;              ///< time of the first beam
  double angle_min_rad = 0.0;        ///< angle of beam 0 in the lidar frame
  double angle_increment_rad = 0.0;  ///< negative for a clockwise lidar
  double time_increment_s = 0.0;     ///< time between beams; 0 means "cannot be de-skewed"
  double scan_time_s = 0.0;          ///< time between scans
  double range_min_m = 0.0;
  double range_max_m = std::numeric_limits<double>::infinity();
  std::vector<double> ranges_m;

  std::size_t size() const { return ranges_m.size(); }
  double beamAngle(std::size_t i) const { return angle_min_rad + i * angle_increment_rad; }
  double beamTime(std::size_t i) const { return stamp_s + i * time_increment_s; }
  /// Time of the last beam.
  double endTime() const { return ranges_m.empty() ? stamp_s : beamTime(ranges_m.size() - 1); }
  /// A beam is valid when its range is finite and inside [range_min, range_max].
  bool valid(std::size_t i) const {
    const double r = ranges_m[i];
    return std::isfinite(r) && r >= range_min_m && r <= range_max_m;
  }
  /// Beam i as a point in the lidar frame, as if every beam were taken at once.
  Eigen::Vector2d point(std::size_t i) const;
  /// All valid beams as points in the lidar frame (no de-skew).
  Points2 points() const;
};

/// A range for every beam of `grid` from points in its lidar frame: each point goes to the beam
/// whose angle is nearest to atan2(y, x); the nearest point wins a bin; empty bins get +inf.
LaserScan repackPoints(const LaserScan& grid,
                       const std::vector<std::optional<Eigen::Vector2d>>& p_lidar);

}  // namespace slamprep
