#include "slamprep/sim/drive/free_space.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <queue>

#include "slamprep/core/error.hpp"

namespace slamprep::sim {
namespace {

struct Step {
  int dx, dy;
  double length;  // in cells
};
constexpr std::array<Step, 8> kSteps{{{1, 0, 1.0},
                                      {-1, 0, 1.0},
                                      {0, 1, 1.0},
                                      {0, -1, 1.0},
                                      {1, 1, std::numbers::sqrt2},
                                      {1, -1, std::numbers::sqrt2},
                                      {-1, 1, std::numbers::sqrt2},
                                      {-1, -1, std::numbers::sqrt2}}};

/// Axis-aligned bounds of every object's footprint (world.hpp outline()).
Eigen::AlignedBox2d worldBounds(const World& world) {
  Eigen::AlignedBox2d box;
  for (const std::vector<Eigen::Vector2d>& line : outline(world))
    for (const Eigen::Vector2d& p : line) box.extend(p);
  return box;
}

/// (cost, cell) ordered by cost, then cell: ties break the same way everywhere.
using Entry = std::pair<double, int>;
using MinQueue = std::priority_queue<Entry, std::vector<Entry>, std::greater<>>;

}  // namespace

FreeSpaceGrid::FreeSpaceGrid(const Scene& scene, double radius_m, double resolution_m,
                             const Eigen::Vector2d& p_seed_m)
    : resolution_m_(resolution_m) {
  const Eigen::AlignedBox2d box = worldBounds(scene.world());
  origin_m_ = box.min() - Eigen::Vector2d::Constant(radius_m);
  const Eigen::Vector2d extent = box.sizes() + Eigen::Vector2d::Constant(2.0 * radius_m);
  const Eigen::Vector2d cells = (extent / resolution_m).array().ceil() + 1.0;
  constexpr double kMaxCells = 4e6;  // ~100 MB of grid and search state
  if (cells.prod() > kMaxCells)
    throw InputError(scene.world().source.string(),
                     "the world is too large for a free-space grid at " +
                         std::to_string(resolution_m) +
                         " m (more than 4e6 cells): raise grid_resolution_m");
  nx_ = static_cast<int>(cells.x());
  ny_ = static_cast<int>(cells.y());
  std::vector<bool> blocked(static_cast<std::size_t>(nx_) * ny_);
  for (int iy = 0; iy < ny_; ++iy)
    for (int ix = 0; ix < nx_; ++ix)
      blocked[index(ix, iy)] = scene.collides(centre(index(ix, iy)), radius_m);
  computeClearance(blocked);
  reachable_.assign(blocked.size(), false);
  // The seed: the unblocked cell nearest to p_seed (the robot may start inside the margin).
  int seed = -1;
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t c = 0; c < blocked.size(); ++c) {
    const double d = (centre(static_cast<int>(c)) - p_seed_m).squaredNorm();
    if (!blocked[c] && d < best) best = d, seed = static_cast<int>(c);
  }
  if (seed < 0)
    throw InputError(scene.world().source.string(),
                     "no free space for the robot's footprint plus clearance");
  floodFrom(seed);
}

Eigen::Vector2d FreeSpaceGrid::centre(int cell) const {
  return origin_m_ + resolution_m_ * Eigen::Vector2d(cell % nx_, cell / nx_);
}

/// Brushfire from the blocked cells: 8-connected chamfer distance (exact along axes and
/// diagonals, at most 8 % long in between).
void FreeSpaceGrid::computeClearance(const std::vector<bool>& blocked) {
  clearance_m_.assign(blocked.size(), std::numeric_limits<double>::infinity());
  MinQueue queue;
  for (std::size_t c = 0; c < blocked.size(); ++c)
    if (blocked[c]) clearance_m_[c] = 0.0, queue.push({0.0, static_cast<int>(c)});
  while (!queue.empty()) {
    const auto [d, c] = queue.top();
    queue.pop();
    if (d > clearance_m_[c]) continue;
    const int ix = c % nx_, iy = c / nx_;
    for (const Step& s : kSteps) {
      const int jx = ix + s.dx, jy = iy + s.dy;
      if (jx < 0 || jy < 0 || jx >= nx_ || jy >= ny_) continue;
      const double dj = d + s.length * resolution_m_;
      if (dj < clearance_m_[index(jx, jy)])
        clearance_m_[index(jx, jy)] = dj, queue.push({dj, index(jx, jy)});
    }
  }
}

void FreeSpaceGrid::floodFrom(int seed) {
  std::vector<int> stack{seed};
  reachable_[seed] = true;
  while (!stack.empty()) {
    const int c = stack.back();
    stack.pop_back();
    const int ix = c % nx_, iy = c / nx_;
    for (const Step& s : kSteps) {
      const int jx = ix + s.dx, jy = iy + s.dy;
      if (jx < 0 || jy < 0 || jx >= nx_ || jy >= ny_) continue;
      const int j = index(jx, jy);
      if (reachable_[j] || clearance_m_[j] == 0.0) continue;
      reachable_[j] = true;
      stack.push_back(j);
    }
  }
  for (std::size_t c = 0; c < reachable_.size(); ++c)
    if (reachable_[c]) free_.push_back(static_cast<int>(c));
}

int FreeSpaceGrid::nearestFree(const Eigen::Vector2d& p_m) const {
  int best = free_.front();
  double best_d = std::numeric_limits<double>::infinity();
  for (const int c : free_) {
    const double d = (centre(c) - p_m).squaredNorm();
    if (d < best_d) best_d = d, best = c;
  }
  return best;
}

/// A* with the Euclidean distance as heuristic (admissible: every step costs at least its
/// length).
std::vector<Eigen::Vector2d> FreeSpaceGrid::path(int from, int to) const {
  std::vector<double> cost(reachable_.size(), std::numeric_limits<double>::infinity());
  std::vector<int> parent(reachable_.size(), -1);
  auto heuristic = [&](int c) { return (centre(c) - centre(to)).norm(); };
  MinQueue open;
  cost[from] = 0.0;
  open.push({heuristic(from), from});
  while (!open.empty()) {
    const auto [f, c] = open.top();
    open.pop();
    if (c == to) break;
    if (f > cost[c] + heuristic(c) + 1e-9) continue;  // a stale entry
    const int ix = c % nx_, iy = c / nx_;
    for (const Step& s : kSteps) {
      const int jx = ix + s.dx, jy = iy + s.dy;
      if (jx < 0 || jy < 0 || jx >= nx_ || jy >= ny_) continue;
      const int j = index(jx, jy);
      if (!reachable_[j]) continue;
      const double penalty = 1.0 + 2.0 * std::max(0.0, 1.0 - clearance_m_[j]);
      const double g = cost[c] + s.length * resolution_m_ * penalty;
      if (g < cost[j]) cost[j] = g, parent[j] = c, open.push({g + heuristic(j), j});
    }
  }
  std::vector<Eigen::Vector2d> points;
  for (int c = to; c != -1; c = parent[c]) points.push_back(centre(c));
  std::reverse(points.begin(), points.end());
  return points;
}

}  // namespace slamprep::sim
