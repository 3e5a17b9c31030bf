#pragma once
// World files: static geometry of the simulated environment, loaded from YAML (docs/worlds.md).

#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

#include "slamprep/core/se2.hpp"
#include "slamprep/sim/physics/transients.hpp"

namespace slamprep::sim {

/// A straight wall segment from -> to, extruded to height_m, thickness centred on the segment.
struct Wall {
  Eigen::Vector2d from_m{0.0, 0.0};  ///< start of the centre line
  Eigen::Vector2d to_m{1.0, 0.0};    ///< end of the centre line
  double thickness_m = 0.1;          ///< full thickness, centred on the segment
  double height_m = 2.0;             ///< extruded from the floor (z = 0) up to here
  bool returns = true;               ///< false: glass, the lidar sees through (faults.enable glass)
};

/// A rectangular block centred at T_world_box.
struct Box {
  SE2 T_world_box;                   ///< centre and yaw of the box
  Eigen::Vector2d size_m{1.0, 1.0};  ///< full extent along the box's x and y axes
  double height_m = 1.0;             ///< extruded from the floor
  bool returns = true;               ///< false: glass, the lidar sees through (faults.enable glass)
};

/// A vertical cylinder standing on the floor.
struct Cylinder {
  Eigen::Vector2d center_m{0.0, 0.0};  ///< axis position in the world
  double radius_m = 0.2;               ///< radius
  double height_m = 1.0;               ///< extruded from the floor
  bool returns = true;  ///< false: glass, the lidar sees through (faults.enable glass)
};

/// A simple polygon (convex or not) extruded to a prism; vertices in either winding order.
struct Polygon {
  std::vector<Eigen::Vector2d> vertices_m;  ///< at least 3, no self-intersection, not closed
  double height_m = 1.0;                    ///< extruded from the floor
  bool returns = true;  ///< false: glass, the lidar sees through (faults.enable glass)
};

/// A low-friction patch of floor (wet tiles, ice): the wheels over it slip (physics mode, with
/// faults.enable floor_patches).
struct FloorPatch {
  std::vector<Eigen::Vector2d> outline_m;  ///< simple polygon, at least 3 vertices
  double friction = 0.1;                   ///< the floor's friction coefficient there (else 1)
};

/// Static geometry of one environment.
struct World {
  std::string name;                       ///< human-readable name
  std::filesystem::path source;           ///< the YAML file it came from
  std::vector<Wall> walls;                ///< wall segments
  std::vector<Box> boxes;                 ///< rectangular blocks
  std::vector<Cylinder> cylinders;        ///< pillars, round tables
  std::vector<Polygon> polygons;          ///< prisms of arbitrary simple outline
  std::vector<FloorPatch> floor_patches;  ///< low-friction floor areas
  /// What is there only for a moment (`transients_file`): the lidar sees it, the physics not.
  std::vector<Transient> transients;
  SE2 T_world_start;  ///< where the robot starts by default
};

/// Loads a world file. Throws InputError("file:line: key", "...") on bad input and unknown keys.
World loadWorld(const std::filesystem::path& file);

/// Corners of a wall's or box's footprint, counter-clockwise, in the world frame.
std::vector<Eigen::Vector2d> footprint(const Wall& wall);
std::vector<Eigen::Vector2d> footprint(const Box& box);

/// 2D outline of all geometry (for plots): closed polylines in the world frame (first vertex
/// repeated at the end). Cylinders are drawn as 48-gons.
std::vector<std::vector<Eigen::Vector2d>> outline(const World& world);

/// True when p lies inside the simple polygon (even-odd rule; points on an edge may go either way).
bool insidePolygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p);

}  // namespace slamprep::sim
