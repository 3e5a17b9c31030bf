#include "slamprep/algo/matching/local_submap.hpp"

#include <cmath>
#include <numbers>

namespace slamprep::algo {

std::pair<std::int64_t, std::int64_t> LocalSubmap::cell(const Eigen::Vector2d& p_world) const {
  // Cells of edge spacing / sqrt(2): two points in one cell are closer than the spacing, so a
  // point the spacing rule admits always finds its cell empty.
  const double edge = params_.voxel_size_m / std::numbers::sqrt2;
  return {static_cast<std::int64_t>(std::floor(p_world.x() / edge)),
          static_cast<std::int64_t>(std::floor(p_world.y() / edge))};
}

std::int64_t LocalSubmap::key(std::int64_t ix, std::int64_t iy) {
  // Two 32-bit cell indices in one key: +-2^31 cells of 3.5 cm span 10^8 m, more than any log.
  return (ix << 32) ^ (iy & 0xffffffffLL);
}

std::int64_t LocalSubmap::voxelKey(const Eigen::Vector2d& p_world) const {
  const auto [ix, iy] = cell(p_world);
  return key(ix, iy);
}

bool LocalSubmap::hasPointNear(const Eigen::Vector2d& p_world) const {
  const auto [ix, iy] = cell(p_world);
  // A point within the spacing lies at most two cells of edge spacing / sqrt(2) away.
  for (std::int64_t dx = -2; dx <= 2; ++dx)
    for (std::int64_t dy = -2; dy <= 2; ++dy) {
      const auto it = voxels_.find(key(ix + dx, iy + dy));
      if (it != voxels_.end() &&
          (points_[it->second].p_world - p_world).norm() < params_.voxel_size_m)
        return true;
    }
  return false;
}

std::size_t LocalSubmap::insert(const Points2& points, const SE2& T_world_sensor, double travel_m) {
  std::size_t added = 0;
  for (const auto& p : points) {
    const Eigen::Vector2d p_world = T_world_sensor * p;
    // Only where the map has no point yet: a wall seen again, slightly misplaced by the drift,
    // would otherwise become a double wall whose neighbourhoods fit no line.
    if (hasPointNear(p_world)) continue;
    voxels_.emplace(voxelKey(p_world), points_.size());
    points_.push_back({p_world, travel_m});
    ++added;
  }
  return added;
}

std::size_t LocalSubmap::prune(const Eigen::Vector2d& p_world_robot, double travel_m) {
  const double max_d2 = params_.max_distance_m * params_.max_distance_m;
  std::vector<SubmapPoint> kept;
  kept.reserve(points_.size());
  for (const auto& s : points_)
    if ((s.p_world - p_world_robot).squaredNorm() <= max_d2 &&
        travel_m - s.inserted_at_travel_m <= params_.max_travel_m)
      kept.push_back(s);
  const std::size_t dropped = points_.size() - kept.size();
  if (dropped == 0) return 0;
  points_ = std::move(kept);
  voxels_.clear();
  for (std::size_t i = 0; i < points_.size(); ++i) voxels_.emplace(voxelKey(points_[i].p_world), i);
  return dropped;
}

Points2 LocalSubmap::pointsIn(const SE2& T_world_ref) const {
  const SE2 T_ref_world = T_world_ref.inverse();
  Points2 out;
  out.reserve(points_.size());
  for (const auto& s : points_) out.push_back(T_ref_world * s.p_world);
  return out;
}

}  // namespace slamprep::algo
