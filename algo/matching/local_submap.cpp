#include "algo/matching/local_submap.hpp"

#include <cmath>

namespace slamprep::algo {

std::int64_t LocalSubmap::voxelKey(const Eigen::Vector2d& p_world) const {
  // Two 32-bit cell indices in one key: +-2^31 voxels of 5 cm span 10^8 m, more than any log.
  const auto ix = static_cast<std::int64_t>(std::floor(p_world.x() / params_.voxel_size_m));
  const auto iy = static_cast<std::int64_t>(std::floor(p_world.y() / params_.voxel_size_m));
  return (ix << 32) ^ (iy & 0xffffffffLL);
}

std::size_t LocalSubmap::insert(const Points2& points, const SE2& T_world_sensor, double travel_m) {
  std::size_t added = 0;
  for (const auto& p : points) {
    const Eigen::Vector2d p_world = T_world_sensor * p;
    if (voxels_.emplace(voxelKey(p_world), points_.size()).second) {
      points_.push_back({p_world, travel_m});
      ++added;
    }
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
