#pragma once
// worlds/box_room.yaml in closed form, for the ray-casting tests.

#include <Eigen/Core>
#include <algorithm>

namespace slamprep::test {

/// Analytic distance from p (inside) along unit d to the box_room walls x = +-3, y = +-2.
inline double boxRoomDistance(const Eigen::Vector2d& p, const Eigen::Vector2d& d) {
  const double tx = d.x() > 0 ? (3 - p.x()) / d.x() : d.x() < 0 ? (-3 - p.x()) / d.x() : 1e300;
  const double ty = d.y() > 0 ? (2 - p.y()) / d.y() : d.y() < 0 ? (-2 - p.y()) / d.y() : 1e300;
  return std::min(tx, ty);
}

}  // namespace slamprep::test
