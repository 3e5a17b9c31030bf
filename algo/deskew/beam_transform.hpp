#pragma once
// The one kernel every de-skew method shares: move each beam's point with its own pose, the poses
// given as knots of a trajectory with constant twist between knots.

#include <Eigen/Core>
#include <optional>
#include <vector>

#include "core/laser_scan.hpp"
#include "core/time_series.hpp"

namespace slamprep::algo {

/// out[i] = T(t_i) * p_L_i for every valid beam (nullopt otherwise), t_i = first_beam_s + i * dt.
/// T(t) follows the knots `T_ref_lidar` geodesically (constant twist between knots, the SE(2)
/// "linear interpolation"); before the first or after the last knot it continues the nearest
/// segment's twist; one knot means one pose for all beams. Cost: no trigonometry per beam, the
/// pose and beam direction advance by constant increments, re-anchored exactly every 64 beams.
void transformBeams(const LaserScan& scan, double first_beam_s, const PoseSeries& T_ref_lidar,
                    std::vector<std::optional<Eigen::Vector2d>>& out);

/// Same as repackPoints() in core, without its per-point remainder(): bins by the nearest beam
/// angle to atan2(y, x), keeps the nearest point per bin, +inf where no point landed.
LaserScan repackScan(const LaserScan& grid,
                     const std::vector<std::optional<Eigen::Vector2d>>& p_lidar);

}  // namespace slamprep::algo
