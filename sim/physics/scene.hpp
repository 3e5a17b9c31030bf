#pragma once
// The Bullet world (double precision): floor plus the static geometry, and its ray casts.

#include <Eigen/Core>
#include <memory>
#include <optional>

#include "slamprep/sim/physics/planar_caster.hpp"
#include "slamprep/sim/physics/world.hpp"

class btDiscreteDynamicsWorld;

namespace slamprep::sim {

/// Collision filter groups: static geometry, the floor, and robot bodies. Ray casts only see
/// kStaticGroup; robots collide with everything.
inline constexpr int kStaticGroup = 1 << 1;  // == btBroadphaseProxy::StaticFilter
inline constexpr int kFloorGroup = 1 << 6;
inline constexpr int kRobotGroup = 1 << 7;

/// Bullet's constraint solver (sequential impulses) for a Scene. The defaults reach the
/// simulator's speed goal (150x real time) with less slip than the 10 iterations and relaxation
/// 1.5 of the caster-body robot before them: see docs/simulate.md, "Performance", for slip
/// against iterations and relaxation.
struct ScenePhysicsParams {
  int solver_iterations = 9;        ///< sequential-impulse iterations per step (Bullet: 10)
  double contact_relaxation = 1.7;  ///< over-relaxation of contact and friction rows (0, 2)
};

/// Bullet world (double precision) with a floor and one static collision object per wall, box,
/// polygon and cylinder. Ray casts go through a PlanarCaster over the same geometry. Not
/// thread-safe (Debian's Bullet): one Scene per thread.
class Scene {
 public:
  explicit Scene(const World& world, const ScenePhysicsParams& params = {});
  ~Scene();
  Scene(const Scene&) = delete;
  Scene& operator=(const Scene&) = delete;

  btDiscreteDynamicsWorld& dynamics();
  const btDiscreteDynamicsWorld& dynamics() const;
  void step(double dt_s);  // stepSimulation(dt_s, 0): fixed step, no substeps
  /// Distance to the first static obstacle along the horizontal ray from origin_m at height_m in
  /// direction yaw_rad (world frame); nullopt when nothing within max_range_m. Ignores robots.
  /// Cast in the ray's plane by PlanarCaster (exact; agrees with castRayBullet).
  std::optional<double> castRay(const Eigen::Vector2d& origin_m, double yaw_rad, double height_m,
                                double max_range_m) const;
  /// The same with the direction as a unit vector (dir = (cos yaw, sin yaw)).
  std::optional<double> castRay(const Eigen::Vector2d& origin_m, const Eigen::Vector2d& dir,
                                double height_m, double max_range_m) const;
  /// The reference for castRay: btCollisionWorld::rayTest against the static collision objects
  /// (triangle meshes and btCylinderShapeZ), cylinder hits refined by the exact ray-circle root.
  std::optional<double> castRayBullet(const Eigen::Vector2d& origin_m, double yaw_rad,
                                      double height_m, double max_range_m) const;
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
