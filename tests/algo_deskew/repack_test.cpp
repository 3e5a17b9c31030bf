#include "slamprep/algo/deskew/repack.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <numbers>

#include "slamprep/core/se2.hpp"

namespace slamprep::algo {
namespace {

using Points = std::vector<std::optional<Eigen::Vector2d>>;
constexpr double kInf = std::numeric_limits<double>::infinity();

LaserScan grid(std::size_t beams, double angle_min_rad, double increment_rad) {
  LaserScan s;
  s.angle_min_rad = angle_min_rad;
  s.angle_increment_rad = increment_rad;
  s.range_min_m = 0.05;
  s.range_max_m = 30.0;
  s.ranges_m.assign(beams, 1.0);
  return s;
}

Eigen::Vector2d direction(double angle) {
  return {std::cos(angle), std::sin(angle)};
}

/// Range along direction u to the line n . p = d.
double rangeToLine(const Eigen::Vector2d& n, double d, const Eigen::Vector2d& u) {
  return d / n.dot(u);
}

// A flat wall (n . p = 2, n at 20 deg) seen within 57 deg of its normal, sampled at angles that are
// not the grid's (0.37 of an increment off, plus a wobble up to 0.1 increment, as after de-skew):
// every ray between two samples gets the wall's exact range. 1e-9 m leaves room for Eq. (2)'s ~10
// roundings at 2-6 m.
TEST(RepackOnGrid, FlatWallAtOffGridAnglesIsExact) {
  for (double sign : {1.0, -1.0}) {  // counterclockwise and clockwise grids
    const double inc = sign * 0.5 * std::numbers::pi / 180.0;
    const LaserScan g = grid(229, 0.35 - sign * 1.0, inc);  // +-57 deg around the normal
    const Eigen::Vector2d n = direction(0.35);
    Points p;
    for (std::size_t i = 0; i < g.size(); ++i) {
      const double angle = g.beamAngle(i) + inc * (0.37 + 0.1 * std::sin(0.7 * i));
      p.push_back(rangeToLine(n, 2.0, direction(angle)) * direction(angle));
    }
    const RepackResult r = repackOnGrid(g, p);
    EXPECT_EQ(r.jumps, 0u);
    EXPECT_EQ(r.bridged, g.size() - 1);
    EXPECT_TRUE(std::isinf(r.scan.ranges_m[0]));  // before the first sample: no surface known
    for (std::size_t j = 1; j < g.size(); ++j)
      EXPECT_NEAR(r.scan.ranges_m[j], rangeToLine(n, 2.0, direction(g.beamAngle(j))), 1e-9) << j;
    EXPECT_EQ(r.filled, g.size() - 1);
  }
}

// A 1 m step between two surfaces (2 m and 3 m, seen 0.5 deg apart) is not bridged: the one grid
// ray between the last near sample and the first far sample is lost; its neighbours are exact.
TEST(RepackOnGrid, DepthJumpIsNotBridged) {
  const double inc = 0.5 * std::numbers::pi / 180.0;
  const LaserScan g = grid(100, -0.4, inc);
  const Eigen::Vector2d n = Eigen::Vector2d::UnitX();
  Points p;
  for (std::size_t i = 0; i < g.size(); ++i) {
    const double angle = g.beamAngle(i) + 0.5 * inc;  // halfway between rays: worst case
    const double d = i < 50 ? 2.0 : 3.0;
    p.push_back(rangeToLine(n, d, direction(angle)) * direction(angle));
  }
  const RepackResult r = repackOnGrid(g, p);
  EXPECT_EQ(r.jumps, 1u);
  EXPECT_TRUE(std::isinf(r.scan.ranges_m[50])) << r.scan.ranges_m[50];  // between p_49 and p_50
  for (std::size_t j = 1; j < g.size(); ++j) {
    if (j == 50) continue;
    EXPECT_NEAR(r.scan.ranges_m[j], rangeToLine(n, j < 50 ? 2.0 : 3.0, direction(g.beamAngle(j))),
                1e-9)
        << j;
  }
  // Eq. (3)'s threshold: a wall seen at 11 deg is bridged, a step seen at 9 deg is not.
  const Eigen::Vector2d a = 2.0 * direction(0.0);
  auto seenAt = [&](double view_deg) {  // b one increment further, on a line at view_deg to ray a
    const double angle_b = inc, view = view_deg * std::numbers::pi / 180.0;
    const double r_b = 2.0 * std::sin(view) / std::sin(view - angle_b);  // law of sines
    return Points{a, r_b * direction(angle_b)};
  };
  EXPECT_EQ(repackOnGrid(grid(3, -inc, inc), seenAt(180.0 - 11.0)).jumps, 0u);
  EXPECT_EQ(repackOnGrid(grid(3, -inc, inc), seenAt(180.0 - 9.0)).jumps, 1u);
}

// Forward/inverse: the points of an on-grid scan repack to the scan itself (to rounding of
// r (cos, sin) and back), no-return beams stay +inf, clockwise or not.
TEST(RepackOnGrid, OnGridScanIsUnchanged) {
  for (double inc : {2 * std::numbers::pi / 720, -2 * std::numbers::pi / 720}) {
    LaserScan scan = grid(720, -2.0, inc);
    for (std::size_t i = 0; i < scan.size(); ++i) scan.ranges_m[i] = 1.0 + 0.3 * (i % 37 == 0);
    scan.ranges_m[3] = kInf;
    scan.ranges_m[100] = kInf;
    scan.ranges_m[101] = kInf;
    Points p;
    for (std::size_t i = 0; i < scan.size(); ++i)
      p.push_back(scan.valid(i) ? std::optional(scan.point(i)) : std::nullopt);
    const RepackResult r = repackOnGrid(scan, p);
    for (std::size_t i = 0; i < scan.size(); ++i) {
      if (scan.valid(i))
        EXPECT_NEAR(r.scan.ranges_m[i], scan.ranges_m[i], 1e-12) << i;
      else
        EXPECT_TRUE(std::isinf(r.scan.ranges_m[i])) << i;
    }
    EXPECT_EQ(r.filled, 717u);
  }
}

// Brute force: every ray against every bridged pair (Eq. (2), nearest wins) with no bin
// bookkeeping, on a moved full-turn scan of a room with a box in it (corners, jumps, the seam).
TEST(RepackOnGrid, MatchesBruteForceOnARoom) {
  const double inc = 2 * std::numbers::pi / 720;
  const LaserScan g = grid(720, -std::numbers::pi, inc);
  // Room |x|, |y| <= 3 and a box [1, 1.5] x [-0.5, 0.5]: ray cast from the origin.
  auto cast = [](const Eigen::Vector2d& u) {
    double best = kInf;
    for (double wall : {3.0, -3.0}) {
      if (u.x() != 0) best = std::min(best, wall / u.x() > 0 ? wall / u.x() : kInf);
      if (u.y() != 0) best = std::min(best, wall / u.y() > 0 ? wall / u.y() : kInf);
    }
    if (u.x() > 0) {
      const double t = 1.0 / u.x();
      if (std::abs(t * u.y()) <= 0.5) best = std::min(best, t);
    }
    return best;
  };
  // Sampled from a pose the de-skew then moved: off-grid, rotated, the seam no longer closed.
  const SE2 T(0.02, -0.01, 0.003);
  Points p;
  for (std::size_t i = 0; i < g.size(); ++i) {
    const Eigen::Vector2d u = direction(g.beamAngle(i) + 0.2 * inc);
    p.push_back(T * (cast(u) * u));
  }
  const RepackParams params;
  const RepackResult r = repackOnGrid(g, p, params);
  const double sin_min = std::sin(params.min_view_angle_deg * std::numbers::pi / 180.0);
  std::size_t lost = 0;
  for (std::size_t j = 0; j < g.size(); ++j) {
    const Eigen::Vector2d u = direction(g.beamAngle(j));
    double expected = kInf;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Eigen::Vector2d a = *p[i], b = *p[(i + 1) % p.size()];
      const double axb = a.x() * b.y() - a.y() * b.x();
      if (std::abs(axb) < sin_min * std::max(a.norm(), b.norm()) * (b - a).norm()) continue;
      const Eigen::Vector2d ab = b - a;
      const double den = u.x() * ab.y() - u.y() * ab.x();
      const double range = axb / den, s = (a.x() * u.y() - a.y() * u.x()) / den;
      if (range > 0 && s >= 0 && s <= 1) expected = std::min(expected, range);
    }
    lost += std::isinf(expected);
    if (std::isinf(expected))
      EXPECT_TRUE(std::isinf(r.scan.ranges_m[j])) << j;
    else
      EXPECT_NEAR(r.scan.ranges_m[j], expected, 1e-12) << j;
  }
  EXPECT_EQ(r.jumps, 2u);  // the box's two silhouette edges
  // The rays between the two points of each jump: 1 or 2, since the 2 cm shift moves the box
  // (at 1 m) up to 0.6 of a beam against the wall (at 3 m).
  EXPECT_EQ(r.filled, g.size() - lost);
  EXPECT_GE(lost, 2u);
  EXPECT_LE(lost, 4u);
}

}  // namespace
}  // namespace slamprep::algo
