#pragma once
// A longer-lived local map for scan-to-map matching (docs/matching.md "Local map"): the points of
// every keyframe inserted, in the world frame, downsampled to one point per voxel (the first one
// kept, so a revisited region is matched against what was seen there first), and forgotten once
// they lie far from the robot or were inserted too many metres of travel ago. A map that outlives
// a few keyframes keeps the reference fixed while the robot moves within a room or comes back to
// it, where a window of the last keyframes drifts along with the robot.

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <utility>
#include <vector>

#include "slamprep/core/laser_scan.hpp"
#include "slamprep/core/se2.hpp"

namespace slamprep::algo {

struct LocalSubmapParams {
  /// Spacing: a point enters only where the map has none closer than this (searched in a grid of
  /// square cells, one point each); finer than the beam spacing at a few metres (1 degree at 5 m =
  /// 0.09 m).
  double voxel_size_m = 0.05;
  /// Points farther than this from the robot are dropped.
  double max_distance_m = 30.0;
  /// Points inserted more than this many metres of travel ago are dropped (a map older than
  /// the matcher's drift allows would pull the scan onto misplaced walls).
  double max_travel_m = 40.0;
};

/// One point of the map: where it is (world frame) and the travel distance when it was inserted.
struct SubmapPoint {
  Eigen::Vector2d p_world;
  double inserted_at_travel_m = 0.0;
};

class LocalSubmap {
 public:
  explicit LocalSubmap(const LocalSubmapParams& params = {}) : params_(params) {}

  /// Adds `points` (in the frame T_world_sensor) where their voxel is still empty; `travel_m` is
  /// the distance travelled so far. Returns how many points were added.
  std::size_t insert(const Points2& points, const SE2& T_world_sensor, double travel_m);

  /// Drops the points farther than max_distance_m from `p_world_robot` or inserted more than
  /// max_travel_m before `travel_m`. Returns how many were dropped.
  std::size_t prune(const Eigen::Vector2d& p_world_robot, double travel_m);

  /// The map's points in the frame T_world_ref, in insertion order.
  Points2 pointsIn(const SE2& T_world_ref) const;

  const std::vector<SubmapPoint>& points() const { return points_; }
  std::size_t size() const { return points_.size(); }

 private:
  std::pair<std::int64_t, std::int64_t> cell(const Eigen::Vector2d& p_world) const;
  static std::int64_t key(std::int64_t ix, std::int64_t iy);
  std::int64_t voxelKey(const Eigen::Vector2d& p_world) const;
  /// A map point closer than voxel_size_m (searched in the 5 x 5 cells around it).
  bool hasPointNear(const Eigen::Vector2d& p_world) const;

  LocalSubmapParams params_;
  std::vector<SubmapPoint> points_;                       ///< insertion order: deterministic
  std::unordered_map<std::int64_t, std::size_t> voxels_;  ///< cell -> index in points_
};

}  // namespace slamprep::algo
