#pragma once
// The simulator tests' world and scenario: an empty square room and a scenario from its segments.

#include <Eigen/Core>
#include <string>

#include "slamprep/sim/drive/scenario.hpp"
#include "slamprep/sim/physics/world.hpp"

namespace slamprep::test {

/// An empty square room, inner faces at +-half_m, robot starting at the origin facing +x.
inline sim::World squareRoom(double half_m) {
  sim::World world;
  world.name = "square";
  world.source = "square_room(test)";
  const double c = half_m + 0.1;  // centre line of 0.2 m thick walls
  const Eigen::Vector2d corners[4] = {{-c, -c}, {c, -c}, {c, c}, {-c, c}};
  for (int k = 0; k < 4; ++k) world.walls.push_back({corners[k], corners[(k + 1) % 4], 0.2, 2.0});
  return world;
}

/// A scenario of the given YAML segment list (each line "  - {...}").
inline sim::Scenario scenario(const std::string& segments_yaml) {
  return sim::parseScenario("segments:\n" + segments_yaml, "test_scenario.yaml");
}

}  // namespace slamprep::test
