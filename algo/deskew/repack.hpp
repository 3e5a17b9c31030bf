#pragma once
// Exact repacking of corrected points onto a regular beam grid (docs/deskew.md, "Repacking").
//
// De-skewed points no longer lie on the scan's beam angles. Grid ray j (direction
// u_j = (cos th_j, sin th_j), th_j = angle_min + j * angle_increment) gets its range from the
// segment between two neighbouring corrected points a = p_i, b = p_{i+1} (consecutive beams,
// both with a return) that it crosses:
//
//   r u_j = a + s (b - a),  s in [0, 1]                                              Eq. (1)
//   r = (a x b) / (u_j x (b - a)),  s = (a x u_j) / (u_j x (b - a))                  Eq. (2)
//
// (x: the 2D cross product; Eq. (2) is Eq. (1) crossed with (b - a) and with u_j). The range is
// exact when the surface between a and b is flat. Several segments crossing one ray: the nearest
// wins (what the lidar would have seen).
//
// Depth-jump test: a and b are bridged only when the segment is seen at an angle of at least
// alpha_min from the rays to both of its ends. In the triangle (lidar, a, b) the sine of the
// angle at a is |a x b| / (|a| |b - a|), at b |a x b| / (|b| |b - a|), so both pass iff
//
//   |a x b| >= sin(alpha_min) max(|a|, |b|) |b - a|                                  Eq. (3)
//
// A flat wall at incidence phi (from its normal) is seen at 90 deg - phi: alpha_min = 10 deg
// keeps walls up to 80 deg of incidence and drops the step between two surfaces at different
// depths (a step dr at range r with beam spacing dth is seen at about atan(r dth / dr): 1.5 deg
// for 1 m at 3 m and 0.5 deg). A step shallower than r dth / tan(alpha_min) (15 cm at 3 m) looks
// like a steep wall and is bridged. Segments spanning more than `max_gap_increments` grid
// increments (the seam of a full turn opened by motion) are not bridged either: nothing was
// measured there. A ray with no bridged segment and no point on it stays +inf (lost).

#include <Eigen/Core>
#include <cstddef>
#include <optional>
#include <vector>

#include "slamprep/core/laser_scan.hpp"

namespace slamprep::algo {

struct RepackParams {
  /// alpha_min of Eq. (3): the smallest angle between a segment and the rays to its ends.
  double min_view_angle_deg = 10.0;
  /// Neighbours farther apart in angle than this many grid increments are not bridged.
  double max_gap_increments = 3.0;
  /// A point this close in angle to a grid ray fills it by itself (a point without bridged
  /// neighbours, an on-grid scan): its range |p|.
  double on_ray_tolerance_rad = 1e-9;
};

struct RepackResult {
  /// The grid's header with one range per grid ray: +inf where no surface crosses the ray.
  LaserScan scan;
  std::size_t filled = 0;   ///< grid rays with a range
  std::size_t bridged = 0;  ///< neighbour pairs interpolated between
  std::size_t jumps = 0;    ///< neighbour pairs refused by Eq. (3) or the gap limit
};

/// Repacks `p_lidar` (one entry per beam of the scan they came from, in beam order, nullopt for
/// no return; the wrap-around pair last -> first counts when the grid spans a full turn) onto
/// the rays of `grid` (its angle_min, angle_increment and size; clockwise grids too).
RepackResult repackOnGrid(const LaserScan& grid,
                          const std::vector<std::optional<Eigen::Vector2d>>& p_lidar,
                          const RepackParams& params = {});

}  // namespace slamprep::algo
