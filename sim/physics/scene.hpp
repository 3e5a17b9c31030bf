#pragma once
// The Bullet world (double precision): floor plus all static geometry in one collision object.

#include <Eigen/Core>
#include <memory>
#include <optional>

#include "sim/physics/world.hpp"

class btDiscreteDynamicsWorld;

namespace slamprep::sim {

/// Collision filter groups: static geometry, the floor, and robot bodies. Ray casts only see
/// kStaticGroup; robots collide with everything.
inline constexpr int kStaticGroup = 1 << 1;  // == btBroadphaseProxy::StaticFilter
inline constexpr int kFloorGroup = 1 << 6;
inline constexpr int kRobotGroup = 1 << 7;

/// Bullet world (double precision) with a floor and all static geometry merged into one collision
/// object for fast ray casts. Not thread-safe (Debian's Bullet): one Scene per thread.
class Scene {
 public:
  explicit Scene(const World& world);
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  btDiscreteDynamicsWorld& dynamics();
  const btDiscreteDynamicsWorld& dynamics() const;
  void step(double dt_s);  // stepSimulation(dt_s, 0): fixed step, no substeps
  /// Distance to the first static obstacle along the horizontal ray from origin_m at height_m in
  /// direction yaw_rad (world frame); nullopt when nothing within max_range_m. Ignores robots.
  std::optional<double> castRay(const Eigen::Vector2d& origin_m, double yaw_rad, double height_m,
                                double max_range_m) const;
  /// True when a vertical disc of radius_m centred at p_world_m overlaps static geometry.
  /// Exact 2D test against the footprints (an obstacle of any height counts).
  bool collides(const Eigen::Vector2d& p_world_m, double radius_m) const;

  const World& world() const;
  /// Simulated time: number of steps times their dt.
  double time_s() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace slamprep::sim
