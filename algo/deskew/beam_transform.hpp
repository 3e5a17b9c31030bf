#pragma once
// The one kernel every de-skew method shares: move each beam's point with its own pose, the poses
// given as knots of a trajectory with constant twist between knots.

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/laser_scan.hpp"
#include "core/se2.hpp"
#include "core/time_series.hpp"

namespace slamprep::algo {

/// A rigid motion as (cos, sin) of its rotation and its translation: composing and inverting
/// need no trigonometry and no angle wrapping (the hot path of de-skew).
struct Rigid2 {
  double c = 1.0, s = 0.0, x = 0.0, y = 0.0;

  static Rigid2 from(const SE2& T);
  /// exp of the twist (rho_x, rho_y, theta), the same map as SE2::exp.
  static Rigid2 exp(const Eigen::Vector3d& xi);
  SE2 toSE2() const;
  /// The twist with exp(log()) = *this, the same map as SE2::log.
  Eigen::Vector3d log() const;
  Rigid2 inverse() const { return {c, -s, -(c * x + s * y), s * x - c * y}; }
  Rigid2 operator*(const Rigid2& b) const {
    return {c * b.c - s * b.s, s * b.c + c * b.s, c * b.x - s * b.y + x, s * b.x + c * b.y + y};
  }
  Eigen::Vector2d apply(double px, double py) const {
    return {c * px - s * py + x, s * px + c * py + y};
  }
};

/// One knot of a trajectory.
struct Knot {
  double stamp_s = 0.0;
  Rigid2 T;
};
/// Knots in increasing time; constant twist (geodesic) between consecutive knots.
using Trajectory = std::vector<Knot>;

Trajectory toTrajectory(const PoseSeries& poses);
/// The pose at t: geodesic between the bracketing knots, the nearest segment's twist continued
/// outside; a single knot everywhere.
Rigid2 poseAt(const Trajectory& trajectory, double t);
/// Every knot left-multiplied by poseAt(t)^-1: the trajectory seen from its pose at t.
Trajectory relativeTo(const Trajectory& trajectory, double t);

/// out[i] = T(t_i) * p_L_i for every valid beam (nullopt otherwise), t_i = first_beam_s + i * dt,
/// T(t) = poseAt(trajectory, t). No trigonometry per beam: the pose and the beam direction advance
/// by constant increments, re-anchored exactly at every knot and every 64 beams.
void transformBeams(const LaserScan& scan, double first_beam_s, const Trajectory& trajectory,
                    std::vector<std::optional<Eigen::Vector2d>>& out);

/// Same as repackPoints() in core, without its per-point remainder(): bins by the nearest beam
/// angle to atan2(y, x), keeps the nearest point per bin, +inf where no point landed.
LaserScan repackScan(const LaserScan& grid,
                     const std::vector<std::optional<Eigen::Vector2d>>& p_lidar);

}  // namespace slamprep::algo
