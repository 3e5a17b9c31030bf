#pragma once
// The walls of a scan-matched map (slamprep twin, docs/twin.md "World"): the matched points in
// an occupancy grid, straight runs of its cells found by a Hough transform and fitted as line
// segments (total least squares), what is left as short walls and posts. Not one box per cell:
// a 10 m wall is one segment.

#include <Eigen/Core>
#include <vector>

#include "slamprep/sim/physics/world.hpp"

namespace slamprep::eval {

/// One matched return in the world frame and where the lidar stood when it took it.
struct MapPoint {
  Eigen::Vector2d p_world;
  Eigen::Vector2d sensor_world;
};

struct WallExtractionParams {
  double cell_m = 0.05;            ///< grid cell; a cell is occupied by >= min_hits points
  int min_hits = 2;                ///< a single stray return does not make a wall
  double line_tolerance_m = 0.05;  ///< a cell belongs to a line within this distance
  double min_length_m = 0.3;       ///< shorter straight runs are left to the clutter pass
  double max_gap_m = 0.25;         ///< a run along a line breaks at a larger gap (a door)
  double angle_step_deg = 1.0;     ///< Hough resolution in angle (rho: line_tolerance_m)
  double thickness_m = 0.04;       ///< thickness of the walls written
  double post_max_extent_m = 0.2;  ///< clutter smaller than this is a post (cylinder)
  /// A wall's noise: the cells along it within this many of its returns' spread (and beyond
  /// line_tolerance_m) go with it, not into walls of their own. A noisy lidar's returns fill
  /// cells a few centimetres off the wall, which would make parallel ghost walls in front of it.
  double fringe_sigmas = 4.0;
};

/// A wall face: the segment where the returns lie, and which side the lidar saw it from.
struct WallSegment {
  Eigen::Vector2d from_m, to_m;
  Eigen::Vector2d normal;  ///< unit, pointing to the side it was seen from
  int cells = 0;           ///< occupied cells on it
  double rms_m = 0.0;      ///< distance of its cells' centroids from the line
  double spread_m = 0.0;   ///< RMS distance of its returns from the line
};

struct Post {
  Eigen::Vector2d center_m;
  double radius_m = 0.0;
};

struct WallMap {
  std::vector<WallSegment> walls;    ///< straight runs, longest first
  std::vector<WallSegment> clutter;  ///< short clusters fitted as short walls
  std::vector<Post> posts;           ///< compact clusters
  int occupied_cells = 0;
  int cells_on_walls = 0;
};

/// Extracts the walls of the map the points make (deterministic: same points, same walls).
WallMap extractWalls(const std::vector<MapPoint>& points, const WallExtractionParams& params = {});

/// A face as the simulator's wall: thickness_m thick, its centre line half of it behind the face
/// (away from the side it was seen from).
sim::Wall faceAsWall(const WallSegment& face, const WallExtractionParams& params);

/// The map's walls, clutter and posts as a world, nothing cut away: what its own scans are
/// compared with.
sim::World wallsAsWorld(const WallMap& map, const WallExtractionParams& params);

}  // namespace slamprep::eval
