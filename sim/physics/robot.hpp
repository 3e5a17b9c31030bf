#pragma once
// The physical differential-drive robot: Bullet rigid bodies, hinge joints and velocity motors.

#include <Eigen/Core>
#include <memory>

#include "slamprep/core/diff_drive.hpp"
#include "slamprep/core/se2.hpp"
#include "slamprep/sim/physics/scene.hpp"

namespace slamprep::sim {

struct RobotConfig {
  DiffDriveParams geometry;           ///< TRUE geometry that Bullet simulates
  double wheel_width_m = 0.03;        ///< cylinder length of each wheel
  double wheel_mass_kg = 0.4;         ///< per wheel
  double chassis_mass_kg = 6.0;       ///< body without wheels
  double max_wheel_torque_nm = 8.0;   ///< motor limit (impulse = torque * dt)
  double wheel_friction = 1.0;        ///< Coulomb friction coefficient, wheel tyre
  double caster_radius_m = 0.03;      ///< spheres front and back
  double caster_friction = 0.0;       ///< 0: frictionless casters, modelled as a level chassis
  double chassis_length_m = 0.40;     ///< along x
  double chassis_width_m = 0.36;      ///< along y; must leave the wheels outside: < b - width
  double chassis_height_m = 0.12;     ///< along z
  double chassis_clearance_m = 0.04;  ///< floor to the chassis underside
  double caster_offset_m = 0.16;      ///< caster centres at +-this along x from the base origin
};

/// Chassis, two driven wheels on hinge joints with velocity motors, casters front and back.
/// Frictionless casters (caster_friction 0, the default) push only straight up, which keeps the
/// chassis level; they are modelled as exactly that, a chassis locked in roll and pitch, with no
/// caster bodies, ball joints or contacts (Bullet then solves 16 constraint rows a step instead
/// of 26). Casters with friction are sphere bodies on ball joints that drag on the floor.
/// The wheels are Bullet cylinders whose collision margin is half their width: a tyre of radius
/// r with a round profile, touching the floor in its mid-plane (contacts exactly b apart).
/// Base pose, velocity and yaw rate are read from the wheel axle. The motors' impulse limit
/// follows the step size Scene::step was last called with (1 ms until the first update()).
/// Adds its bodies to the scene and removes them when destroyed: destroy it before the Scene.
class Robot {
 public:
  Robot(Scene& scene, const RobotConfig& config, const SE2& T_world_base0);
  ~Robot();
  Robot(const Robot&) = delete;
  Robot& operator=(const Robot&) = delete;

  const RobotConfig& config() const;
  void setWheelRateTargets(double left_radps, double right_radps);
  /// Friction coefficient of each tyre from the next step on (Bullet multiplies it by the
  /// floor's): how a low-friction floor patch acts on the wheel above it.
  void setWheelFriction(double left, double right);
  /// Holds the body still (a lifted robot, or one pinned against an obstacle) or lets it go: held,
  /// the chassis is a static body and the robot's bodies lose every velocity but the wheels'
  /// spin, so the wheels turn at their motor targets, skidding on the floor under their own
  /// weight, while the base stays where it is. Let go, it is a dynamic body again, at rest.
  void setHeld(bool held);
  bool held() const;
  /// Call after every Scene::step: reads the chassis pose and unwraps the wheel angles.
  void update();
  SE2 T_world_base() const;        // base frame: between the wheel contact points, x forward
  double wheelAngleLeft() const;   // cumulative wheel rotation relative to the chassis (rad)
  double wheelAngleRight() const;  // positive = rolls the robot forward; unwrapped
  Eigen::Vector2d linearVelocity_world() const;  // of the base origin, m/s
  double yawRate() const;                        // rad/s
  /// Angle between the chassis' z axis and the world's z axis (rad): 0 when level.
  double tilt_rad() const;
  /// Height of the base origin above the floor (m): 0 when the wheels rest on it.
  double baseHeight_m() const;
  /// Measured wheel rates relative to the chassis (rad/s), positive forward.
  double wheelRateLeft() const;
  double wheelRateRight() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace slamprep::sim
