#include "algo/deskew/beam_transform.hpp"

#include <cmath>
#include <numbers>

namespace slamprep::algo {
namespace {

/// A rigid motion as (cos, sin, x, y): composing needs no trigonometry.
struct Rigid {
  double c = 1.0, s = 0.0, x = 0.0, y = 0.0;

  static Rigid from(const SE2& T) { return {std::cos(T.yaw), std::sin(T.yaw), T.x, T.y}; }
  Rigid operator*(const Rigid& b) const {
    return {c * b.c - s * b.s, s * b.c + c * b.s, c * b.x - s * b.y + x, s * b.x + c * b.y + y};
  }
  Eigen::Vector2d apply(double px, double py) const {
    return {c * px - s * py + x, s * px + c * py + y};
  }
};

constexpr std::size_t kReanchorEvery = 64;

/// Segment k of the knots: [stamp_k, stamp_{k+1}] with its twist per second.
struct Segment {
  SE2 T_start;
  double t_start = 0.0, t_end = 0.0;
  Eigen::Vector3d twist_per_s = Eigen::Vector3d::Zero();

  SE2 at(double t) const { return T_start * SE2::exp(twist_per_s * (t - t_start)); }
};

Segment segment(const PoseSeries& knots, std::size_t k) {
  Segment seg{knots[k].value, knots[k].stamp_s, knots[k + 1].stamp_s, Eigen::Vector3d::Zero()};
  seg.twist_per_s = between(knots[k].value, knots[k + 1].value).log() / (seg.t_end - seg.t_start);
  return seg;
}

}  // namespace

void transformBeams(const LaserScan& scan, double first_beam_s, const PoseSeries& T_ref_lidar,
                    std::vector<std::optional<Eigen::Vector2d>>& out) {
  const std::size_t n = scan.size();
  out.assign(n, std::nullopt);
  if (n == 0 || T_ref_lidar.empty()) return;
  const double dt = scan.time_increment_s;
  const double cd = std::cos(scan.angle_increment_rad), sd = std::sin(scan.angle_increment_rad);
  const std::size_t knots = T_ref_lidar.size();
  std::size_t k = 0;  // current segment index (knots >= 2)
  Segment seg;
  Rigid T, step;  // pose at beam i, and the increment over one beam
  double ca = 0.0, sa = 0.0;
  bool anchor = true;
  for (std::size_t i = 0; i < n; ++i) {
    const double t = first_beam_s + i * dt;
    if (knots >= 2) {
      std::size_t k_new = k;
      while (k_new + 2 < knots && T_ref_lidar[k_new + 1].stamp_s < t) ++k_new;
      if (k_new != k || i == 0) {
        k = k_new;
        seg = segment(T_ref_lidar, k);
        step = Rigid::from(SE2::exp(seg.twist_per_s * dt));
        anchor = true;
      }
    }
    if (anchor || i % kReanchorEvery == 0) {  // exact pose and direction, no drift
      T = Rigid::from(knots >= 2 ? seg.at(t) : T_ref_lidar[0].value);
      ca = std::cos(scan.beamAngle(i));
      sa = std::sin(scan.beamAngle(i));
      anchor = false;
    }
    if (scan.valid(i)) out[i] = T.apply(scan.ranges_m[i] * ca, scan.ranges_m[i] * sa);
    if (knots >= 2) T = T * step;
    const double c_next = ca * cd - sa * sd;
    sa = sa * cd + ca * sd;
    ca = c_next;
  }
}

LaserScan repackScan(const LaserScan& grid,
                     const std::vector<std::optional<Eigen::Vector2d>>& p_lidar) {
  LaserScan out = grid;
  const double inf = std::numeric_limits<double>::infinity();
  out.ranges_m.assign(grid.size(), inf);
  if (grid.size() == 0 || grid.angle_increment_rad == 0.0) return out;
  const double bins_per_turn = 2.0 * std::numbers::pi / std::abs(grid.angle_increment_rad);
  const double inv_increment = 1.0 / grid.angle_increment_rad;
  const long size = static_cast<long>(grid.size());
  for (const auto& p : p_lidar) {
    if (!p) continue;
    // Bin offset from angle_min, wrapped into [-0.5, turn - 0.5) bins without remainder().
    double k = (std::atan2(p->y(), p->x()) - grid.angle_min_rad) * inv_increment;
    k -= bins_per_turn * std::floor((k + 0.5) / bins_per_turn);
    const long bin = std::lround(k);
    if (bin < 0 || bin >= size) continue;
    out.ranges_m[bin] = std::min(out.ranges_m[bin], p->norm());
  }
  return out;
}

}  // namespace slamprep::algo
