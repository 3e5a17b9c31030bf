#pragma once
// The `explore` segment: random smooth driving that stays in the world's free space, for any
// duration. Random goals drawn from the free space (a clearance away from every obstacle), an A*
// path to each, followed by pure pursuit under the speed, turn-rate and acceleration limits.
// A scenario does not know its world, so the segment is planned when the simulator has both.

#include <cstdint>

#include "slamprep/core/se2.hpp"
#include "slamprep/sim/drive/config.hpp"
#include "slamprep/sim/drive/scenario.hpp"
#include "slamprep/sim/physics/scene.hpp"

namespace slamprep::sim {

/// The keys of an `explore` segment (docs/simulate.md).
struct ExploreParams {
  double duration_s = 0.0;     ///< length of the segment, rest to rest
  std::uint64_t seed = 1;      ///< goals and speeds; the same seed gives the same path
  double min_speed_mps = 0.2;  ///< cruise speed of each leg, uniform in [min, max]
  double max_speed_mps = 0.5;
  double max_turn_rate_radps = 1.0;  ///< |w| limit of the follower
  double clearance_m = 0.3;          ///< goals and paths keep this beyond footprint + margin
  double lookahead_m = 0.6;          ///< pure-pursuit look-ahead distance
  double min_goal_distance_m = 2.0;  ///< goals at least this far from the robot (when possible)
  double grid_resolution_m = 0.1;    ///< cell size of the free-space grid
  double control_period_s = 0.1;     ///< a twist knot every period (linear in between)
  AccelerationLimits limits;         ///< the scenario's limits where the segment was written
};

/// The scenario with every `explore` segment planned in `scene` from the pose the commanded drive
/// reaches there (replayed as checkPathInWorld does, from T_world_start). Other segments are
/// copied unchanged. Deterministic: the same inputs give the same knots, bit for bit.
Scenario planExplore(const Scene& scene, const Scenario& scenario, const SimConfig& config,
                     const SE2& T_world_start);

}  // namespace slamprep::sim
