#include "slamprep/eval/bench/transient_returns.hpp"

#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace slamprep::eval {
namespace {

/// Every return placed, transient or not, as TransientReturns::points keeps the transient ones.
using Return = TransientPoint;

/// Returns binned in square cells of the search radius, each cell's in time order.
class ReturnGrid {
 public:
  ReturnGrid(const std::vector<Return>& returns, double cell_m)
      : returns_(returns), cell_m_(cell_m) {
    for (std::size_t i = 0; i < returns.size(); ++i)
      cells_[key(cellOf(returns[i].p_world))].push_back(i);
  }

  /// Whether a return at least gap_s from `r` in time lies within radius_m of it.
  bool supported(const Return& r, double gap_s, double radius_m) const {
    const auto [cx, cy] = cellOf(r.p_world);
    for (std::int64_t dx = -1; dx <= 1; ++dx)
      for (std::int64_t dy = -1; dy <= 1; ++dy)
        if (const auto it = cells_.find(key({cx + dx, cy + dy}));
            it != cells_.end() && supportedIn(it->second, r, gap_s, radius_m))
          return true;
    return false;
  }

 private:
  using Cell = std::pair<std::int64_t, std::int64_t>;
  Cell cellOf(const Eigen::Vector2d& p) const {
    return {std::int64_t(std::floor(p.x() / cell_m_)), std::int64_t(std::floor(p.y() / cell_m_))};
  }
  static std::int64_t key(Cell c) { return (c.first << 32) ^ (c.second & 0xffffffff); }

  /// The cell's returns earlier than t - gap from its start, later than t + gap from its end.
  bool supportedIn(const std::vector<std::size_t>& cell, const Return& r, double gap_s,
                   double radius_m) const {
    const auto near = [&](std::size_t i) {
      return (returns_[i].p_world - r.p_world).squaredNorm() <= radius_m * radius_m;
    };
    for (std::size_t i : cell) {
      if (returns_[i].t_s > r.t_s - gap_s) break;
      if (near(i)) return true;
    }
    for (auto it = cell.rbegin(); it != cell.rend(); ++it) {
      if (returns_[*it].t_s < r.t_s + gap_s) break;
      if (near(*it)) return true;
    }
    return false;
  }

  const std::vector<Return>& returns_;
  double cell_m_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells_;
};

std::vector<Return> placedReturns(const Dataset& d, const PoseSeries& T_world_base,
                                  const std::vector<char>& use, double max_range_m,
                                  const TransientParams& p) {
  std::vector<Return> out;
  for (std::size_t k = 0; k < d.scans.size() && k < use.size(); ++k) {
    if (!use[k]) continue;
    const LaserScan& s = d.scans[k].scan;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (!s.valid(i) || s.ranges_m[i] < p.min_range_m || s.ranges_m[i] > max_range_m) continue;
      const auto T = T_world_base.at(s.beamTime(i));
      if (!T) continue;
      const SE2 T_world_lidar = *T * d.info.T_base_lidar;
      out.push_back({T_world_lidar * s.point(i), T_world_lidar.translation(), s.beamTime(i)});
    }
  }
  return out;
}

}  // namespace

TransientReturns transientReturns(const Dataset& d, const PoseSeries& T_world_base,
                                  const std::vector<char>& use, double max_range_m,
                                  const TransientParams& p) {
  const std::vector<Return> returns = placedReturns(d, T_world_base, use, max_range_m, p);
  // Cells of the radius: every return within it lies in the 3 x 3 cells about the query's.
  const ReturnGrid grid(returns, p.radius_m);
  TransientReturns out;
  out.returns = returns.size();
  for (const Return& r : returns) {
    if (grid.supported(r, p.min_gap_s, p.radius_m)) continue;
    ++out.transient;
    if (p.keep_points) out.points.push_back(r);
  }
  return out;
}

}  // namespace slamprep::eval
