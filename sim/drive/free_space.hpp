#pragma once
// The world's free space as an occupancy grid for planning: a cell is free when a disc of the
// planning radius at its centre clears all static geometry and the cell is reachable from the
// seed position. Paths are 8-connected A* that prefers cells far from obstacles.

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "slamprep/sim/physics/scene.hpp"

namespace slamprep::sim {

class FreeSpaceGrid {
 public:
  /// Rasterises the world's bounding box (plus one radius) at resolution_m; free cells are those
  /// with Scene::collides(centre, radius_m) false that are 8-connected to the free cell nearest
  /// p_seed_m. Throws InputError when no free cell exists.
  FreeSpaceGrid(const Scene& scene, double radius_m, double resolution_m,
                const Eigen::Vector2d& p_seed_m);

  /// Indices of the reachable free cells, in row-major order.
  const std::vector<int>& freeCells() const { return free_; }
  Eigen::Vector2d centre(int cell) const;
  /// The reachable free cell nearest to p (by grid distance from p's cell).
  int nearestFree(const Eigen::Vector2d& p_m) const;
  /// Distance (m) from a cell's centre to the nearest blocked cell (chamfer estimate).
  double clearance_m(int cell) const { return clearance_m_[cell]; }

  /// Cell centres from `from` to `to` (both reachable free cells), shortest under the cost
  /// length * (1 + 2 max(0, 1 - clearance / 1 m)): paths keep ~1 m from obstacles where they can.
  std::vector<Eigen::Vector2d> path(int from, int to) const;

 private:
  int index(int ix, int iy) const { return iy * nx_ + ix; }
  void computeClearance(const std::vector<bool>& blocked);
  void floodFrom(int seed);

  Eigen::Vector2d origin_m_;  ///< centre of cell (0, 0)
  double resolution_m_;
  int nx_ = 0, ny_ = 0;
  std::vector<bool> reachable_;
  std::vector<double> clearance_m_;
  std::vector<int> free_;
};

}  // namespace slamprep::sim
