#pragma once
// Returns no other moment of a recording supports (docs/twin.md "Transient returns"): people
// walking by, doors, things moved, clutter seen once. A matcher pulled by them errs slowly in
// heading; a world of still walls has none.

#include <vector>

#include "slamprep/core/dataset.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep::eval {

struct TransientParams {
  double min_gap_s = 3.0;    ///< support must come from a return at least this far in time
  double radius_m = 0.05;    ///< and lie this close (the matched map's voxel)
  double min_range_m = 0.5;  ///< nearer returns: the robot's own body and what it pushes
  bool keep_points = false;  ///< TransientReturns::points wanted
};

/// A transient return where it was seen: the hit, the lidar it was seen from, when.
struct TransientPoint {
  Eigen::Vector2d p_world, origin_world;
  double t_s = 0.0;
};

struct TransientReturns {
  std::size_t returns = 0;             ///< valid returns placed in the world
  std::size_t transient = 0;           ///< of those, without support
  std::vector<TransientPoint> points;  ///< the transient ones, with TransientParams::keep_points
  double fraction() const { return returns ? double(transient) / double(returns) : 0.0; }
};

/// Each valid return of the scans with `use[k]` (min_range_m to max_range_m) placed in the world
/// from T_world_base interpolated to its beam's time; transient where no such return at least
/// min_gap_s earlier or later lies within radius_m. A robot that never comes back sees a wall
/// for as long as it drives past it, so a still world gives few (a twin's: 0.8-3.7 %).
TransientReturns transientReturns(const Dataset& dataset, const PoseSeries& T_world_base,
                                  const std::vector<char>& use, double max_range_m,
                                  const TransientParams& params = {});

}  // namespace slamprep::eval
