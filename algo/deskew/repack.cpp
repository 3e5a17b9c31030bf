#include "slamprep/algo/deskew/repack.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace slamprep::algo {
namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// The grid in bin coordinates: k(th) = (th - angle_min) / angle_increment, wrapped into
/// [-0.5, turn - 0.5) where turn is the number of bins in 2 pi.
class GridRays {
 public:
  explicit GridRays(const LaserScan& grid)
      : grid_(grid),
        turn_(2.0 * std::numbers::pi / std::abs(grid.angle_increment_rad)),
        whole_turn_(std::abs(turn_ - std::round(turn_)) < 1e-6 ? std::lround(turn_) : 0) {}

  double binOf(const Eigen::Vector2d& p) const {
    const double k = (std::atan2(p.y(), p.x()) - grid_.angle_min_rad) / grid_.angle_increment_rad;
    return k - turn_ * std::floor((k + 0.5) / turn_);
  }
  /// Bins from a to b the short way round (negative when b is behind a).
  double binsBetween(double k_a, double k_b) const {
    const double d = k_b - k_a;
    return d - turn_ * std::floor(d / turn_ + 0.5);
  }
  /// Grid index of integer bin j (taken modulo a whole turn when the grid has one); -1 if none.
  long index(long j) const {
    const auto size = static_cast<long>(grid_.size());
    if (j >= 0 && j < size) return j;  // the common case: no division
    if (whole_turn_ > 0) j = ((j % whole_turn_) + whole_turn_) % whole_turn_;
    return j >= 0 && j < size ? j : -1;
  }
  /// Whether the grid closes on itself: its last ray is one increment before its first.
  bool fullTurn() const {
    return std::abs(grid_.size() * std::abs(grid_.angle_increment_rad) - 2.0 * std::numbers::pi) <
           0.5 * std::abs(grid_.angle_increment_rad);
  }
  /// Unit direction of ray j, computed once per grid (the same grid comes scan after scan).
  const Eigen::Vector2d& direction(long j) const { return directions()[j]; }

 private:
  const std::vector<Eigen::Vector2d>& directions() const {
    struct Cache {
      double angle_min = std::numeric_limits<double>::quiet_NaN(), increment = 0.0;
      std::vector<Eigen::Vector2d> u;
    };
    thread_local Cache cache;
    if (cache.angle_min != grid_.angle_min_rad || cache.increment != grid_.angle_increment_rad ||
        cache.u.size() != grid_.size()) {
      cache.u.resize(grid_.size());
      for (std::size_t j = 0; j < grid_.size(); ++j)
        cache.u[j] = {std::cos(grid_.beamAngle(j)), std::sin(grid_.beamAngle(j))};
      cache.angle_min = grid_.angle_min_rad;
      cache.increment = grid_.angle_increment_rad;
    }
    return cache.u;
  }

  const LaserScan& grid_;
  double turn_;
  long whole_turn_;
};

/// Eq. (3): the segment a-b is seen at least alpha_min from the rays to both ends.
bool sameSurface(const Eigen::Vector2d& a, const Eigen::Vector2d& b, double sin_min_angle) {
  return std::abs(cross(a, b)) >= sin_min_angle * std::max(a.norm(), b.norm()) * (b - a).norm();
}

/// Eq. (2) for every grid ray between bins k_a and k_a + d: the nearest range wins.
void fillSegment(const GridRays& rays, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                 double k_a, double d, std::vector<double>& ranges) {
  const Eigen::Vector2d ab = b - a;
  const double a_cross_b = cross(a, b);
  const auto first = static_cast<long>(std::ceil(std::min(k_a, k_a + d)));
  const auto last = static_cast<long>(std::floor(std::max(k_a, k_a + d)));
  for (long j = first; j <= last; ++j) {
    const long i = rays.index(j);
    if (i < 0) continue;
    const Eigen::Vector2d& u = rays.direction(i);
    const double denominator = cross(u, ab);
    if (denominator == 0.0) continue;  // the ray runs along the segment
    const double r = a_cross_b / denominator, s = cross(a, u) / denominator;
    constexpr double kSlack = 1e-12;  // the bins of a and b are rounded
    if (r > 0.0 && s >= -kSlack && s <= 1.0 + kSlack) ranges[i] = std::min(ranges[i], r);
  }
}

}  // namespace

RepackResult repackOnGrid(const LaserScan& grid,
                          const std::vector<std::optional<Eigen::Vector2d>>& p_lidar,
                          const RepackParams& params) {
  RepackResult result;
  result.scan = grid;
  std::vector<double>& ranges = result.scan.ranges_m;
  ranges.assign(grid.size(), std::numeric_limits<double>::infinity());
  if (grid.size() == 0 || grid.angle_increment_rad == 0.0) return result;
  const GridRays rays(grid);
  const double sin_min_angle = std::sin(params.min_view_angle_deg * std::numbers::pi / 180.0);
  const double on_ray_bins = params.on_ray_tolerance_rad / std::abs(grid.angle_increment_rad);
  const std::size_t n = p_lidar.size();
  std::vector<double> bins(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (!p_lidar[i]) continue;
    bins[i] = rays.binOf(*p_lidar[i]);
    const double nearest = std::round(bins[i]);
    const long j = rays.index(static_cast<long>(nearest));
    if (j >= 0 && std::abs(bins[i] - nearest) <= on_ray_bins)
      ranges[j] = std::min(ranges[j], p_lidar[i]->norm());
  }
  auto bridge = [&](std::size_t ia, std::size_t ib) {
    if (!p_lidar[ia] || !p_lidar[ib]) return;
    const Eigen::Vector2d &a = *p_lidar[ia], &b = *p_lidar[ib];
    const double d = rays.binsBetween(bins[ia], bins[ib]);
    if (std::abs(d) > params.max_gap_increments || !sameSurface(a, b, sin_min_angle)) {
      ++result.jumps;
      return;
    }
    ++result.bridged;
    fillSegment(rays, a, b, bins[ia], d, ranges);
  };
  for (std::size_t i = 0; i + 1 < n; ++i) bridge(i, i + 1);
  if (n >= 2 && rays.fullTurn()) bridge(n - 1, 0);
  result.filled = static_cast<std::size_t>(
      std::count_if(ranges.begin(), ranges.end(), [](double r) { return std::isfinite(r); }));
  return result;
}

}  // namespace slamprep::algo
