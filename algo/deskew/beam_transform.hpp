#pragma once
// The one kernel every de-skew method shares: move each beam's point with its own pose, the poses
// given as knots of a trajectory with constant twist between knots.

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "slamprep/core/laser_scan.hpp"
#include "slamprep/core/se2.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep::algo {

/// One knot of a trajectory.
struct Knot {
  double stamp_s = 0.0;
  SE2 T;
};
/// Knots in increasing time; constant twist (geodesic) between consecutive knots.
using Trajectory = std::vector<Knot>;

Trajectory toTrajectory(const PoseSeries& poses);
/// The pose at t: geodesic between the bracketing knots, the nearest segment's twist continued
/// outside; a single knot everywhere.
SE2 poseAt(const Trajectory& trajectory, double t);
/// Every knot left-multiplied by poseAt(t)^-1: the trajectory seen from its pose at t.
Trajectory relativeTo(const Trajectory& trajectory, double t);

/// out[i] = T(t_i) * p_L_i for every valid beam (nullopt otherwise), t_i = first_beam_s + i * dt,
/// T(t) = poseAt(trajectory, t). No trigonometry per beam: the pose and the beam direction advance
/// by constant increments, re-anchored exactly at every knot and every 64 beams.
void transformBeams(const LaserScan& scan, double first_beam_s, const Trajectory& trajectory,
                    std::vector<std::optional<Eigen::Vector2d>>& out);

}  // namespace slamprep::algo
