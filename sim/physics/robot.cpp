#include "slamprep/sim/physics/robot.hpp"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

namespace slamprep::sim {
namespace {

/// A rigid body that owns its shape. No motion state: poses are read from getWorldTransform(),
/// so Bullet has nothing to synchronise after a step.
struct Body {
  std::unique_ptr<btCollisionShape> shape;
  std::unique_ptr<btRigidBody> body;
};

Body makeBody(std::unique_ptr<btCollisionShape> shape, double mass_kg, const btTransform& pose,
              double friction) {
  Body b;
  btVector3 inertia(0, 0, 0);
  shape->calculateLocalInertia(mass_kg, inertia);
  b.shape = std::move(shape);
  btRigidBody::btRigidBodyConstructionInfo info(mass_kg, nullptr, b.shape.get(), inertia);
  info.m_startWorldTransform = pose;
  info.m_friction = friction;
  info.m_rollingFriction = 0.0;
  info.m_restitution = 0.0;
  b.body = std::make_unique<btRigidBody>(info);
  b.body->setActivationState(DISABLE_DEACTIVATION);  // a parked robot must still obey commands
  // No gyroscopic term: the hinges hold the wheel axes, and Bullet's implicit gyroscopic step
  // on a wheel spinning at 10 rad/s while the robot yaws added drift (spin in place: 0.39 mm
  // with it, 0.16 mm without; sim_slip_table) and 5 % of the step's time.
  b.body->setFlags(b.body->getFlags() & ~BT_ENABLE_GYROSCOPIC_FORCE_IMPLICIT_BODY);
  return b;
}

btTransform pose3d(const SE2& T_world_base, const btVector3& p_base) {
  btTransform T;
  T.setBasis(btMatrix3x3(btQuaternion(btVector3(0, 0, 1), T_world_base.yaw)));
  T.setOrigin(btVector3(T_world_base.x, T_world_base.y, 0) + T.getBasis() * p_base);
  return T;
}

/// Unwraps a joint angle reported in (-pi, pi]: adds the wrapped difference to the total.
struct Unwrapper {
  double last_rad = 0.0;
  double total_rad = 0.0;
  void update(double angle_rad) {
    total_rad += normalizeAngle(angle_rad - last_rad);
    last_rad = angle_rad;
  }
};

}  // namespace

struct Robot::Impl {
  Scene& scene;
  RobotConfig config;
  double chassis_z_m = 0.0;  // chassis centre of mass above the base origin
  Body chassis, wheel_left, wheel_right;
  Body caster_front, caster_back;  // only with caster friction; empty otherwise
  std::unique_ptr<btHingeConstraint> hinge_left, hinge_right;
  std::unique_ptr<btPoint2PointConstraint> joint_front, joint_back;
  Unwrapper angle_left, angle_right;
  int chassis_mask = 0;  // collision mask the chassis was added with
  bool held = false;
  double motor_dt_s = 0.001;  // step the motor impulse limit was set for
  double last_time_s = 0.0;

  Impl(Scene& s, const RobotConfig& c, const SE2& T_world_base0);
  ~Impl();
  void setMotorLimit(double dt_s);
  /// Caster spheres on ball joints, for casters with friction.
  void addCasters(const SE2& T_world_base0, int collision_mask);
  /// Wheel rotation relative to the chassis, positive forward: the encoder reading.
  double hingeAngle(btHingeConstraint& hinge) const { return -hinge.getHingeAngle(); }
};

Robot::Impl::Impl(Scene& s, const RobotConfig& c, const SE2& T0) : scene(s), config(c) {
  const DiffDriveParams& g = config.geometry;
  assert(g.radius_left_m > 0 && g.radius_right_m > 0 && g.wheel_base_m > 0);
  assert(config.chassis_width_m < g.wheel_base_m - config.wheel_width_m);
  chassis_z_m = config.chassis_clearance_m + config.chassis_height_m / 2;
  const btVector3 half(config.chassis_length_m / 2, config.chassis_width_m / 2,
                       config.chassis_height_m / 2);
  chassis = makeBody(std::make_unique<btBoxShape>(half), config.chassis_mass_kg,
                     pose3d(T0, btVector3(0, 0, chassis_z_m)), 0.5);

  // Wheels: cylinders along the chassis y axis, centres b apart, touching the floor.
  auto wheel = [&](double radius_m, double y_m) {
    // Collision margin = half the width: the core is a flat disc of radius r - w/2, and the
    // collision surface a tyre of radius r with a round profile (radius w/2). It touches the
    // floor in its mid-plane, so the contact points are exactly b apart; a flat-edged cylinder
    // touches at an edge instead and turns like b + w (measured: 5 % slow spin).
    auto shape =
        std::make_unique<btCylinderShape>(btVector3(radius_m, config.wheel_width_m / 2, radius_m));
    shape->setMargin(config.wheel_width_m / 2);
    return makeBody(std::move(shape), config.wheel_mass_kg, pose3d(T0, btVector3(0, y_m, radius_m)),
                    config.wheel_friction);
  };
  wheel_left = wheel(g.radius_left_m, g.wheel_base_m / 2);
  wheel_right = wheel(g.radius_right_m, -g.wheel_base_m / 2);
  auto hinge = [&](Body& w, double radius_m, double y_m) {
    // A = chassis, B = wheel, axis +y in both frames.
    auto h = std::make_unique<btHingeConstraint>(
        *chassis.body, *w.body, btVector3(0, y_m, radius_m - chassis_z_m), btVector3(0, 0, 0),
        btVector3(0, 1, 0), btVector3(0, 1, 0));
    scene.dynamics().addConstraint(h.get(), true);  // no collisions chassis <-> wheel
    return h;
  };

  // Collision pairs: the robot's bodies never touch each other (joined by the joints or apart),
  // and the chassis box never touches the floor (it rides chassis_clearance_m above it; the
  // simulator's tilt check refuses the run long before), so Bullet need not test those pairs
  // every step. Static geometry and the floor are seen by every body that can reach them.
  const int mask = btBroadphaseProxy::AllFilter ^ kRobotGroup;
  for (Body* b : {&wheel_left, &wheel_right})
    scene.dynamics().addRigidBody(b->body.get(), kRobotGroup, mask);
  chassis_mask = mask ^ kFloorGroup;
  scene.dynamics().addRigidBody(chassis.body.get(), kRobotGroup, chassis_mask);
  hinge_left = hinge(wheel_left, g.radius_left_m, g.wheel_base_m / 2);
  hinge_right = hinge(wheel_right, g.radius_right_m, -g.wheel_base_m / 2);
  if (config.caster_friction > 0)
    addCasters(T0, mask);
  else
    chassis.body->setAngularFactor(btVector3(0, 0, 1));  // frictionless casters: level chassis
  setMotorLimit(motor_dt_s);
  last_time_s = scene.time_s();
  angle_left.last_rad = hingeAngle(*hinge_left);
  angle_right.last_rad = hingeAngle(*hinge_right);
}

Robot::Impl::~Impl() {
  for (btTypedConstraint* c : std::initializer_list<btTypedConstraint*>{
           hinge_left.get(), hinge_right.get(), joint_front.get(), joint_back.get()})
    if (c) scene.dynamics().removeConstraint(c);
  for (Body* b : {&chassis, &wheel_left, &wheel_right, &caster_front, &caster_back})
    if (b->body) scene.dynamics().removeRigidBody(b->body.get());
}

void Robot::Impl::addCasters(const SE2& T0, int collision_mask) {
  // Spheres on ball joints under the front and back of the chassis.
  const double rc = config.caster_radius_m;
  auto caster = [&](double x_m) {
    Body b = makeBody(std::make_unique<btSphereShape>(rc), 0.1, pose3d(T0, btVector3(x_m, 0, rc)),
                      config.caster_friction);
    scene.dynamics().addRigidBody(b.body.get(), kRobotGroup, collision_mask);
    return b;
  };
  auto ball = [&](Body& b, double x_m) {
    auto j = std::make_unique<btPoint2PointConstraint>(
        *chassis.body, *b.body, btVector3(x_m, 0, rc - chassis_z_m), btVector3(0, 0, 0));
    scene.dynamics().addConstraint(j.get(), true);
    return j;
  };
  caster_front = caster(config.caster_offset_m);
  caster_back = caster(-config.caster_offset_m);
  joint_front = ball(caster_front, config.caster_offset_m);
  joint_back = ball(caster_back, -config.caster_offset_m);
}

void Robot::Impl::setMotorLimit(double dt_s) {
  motor_dt_s = dt_s;
  // Bullet's motor limit is an impulse per step: torque * dt.
  for (btHingeConstraint* h : {hinge_left.get(), hinge_right.get()})
    h->setMaxMotorImpulse(config.max_wheel_torque_nm * dt_s);
}

Robot::Robot(Scene& scene, const RobotConfig& config, const SE2& T_world_base0)
    : impl_(std::make_unique<Impl>(scene, config, T_world_base0)) {
  setWheelRateTargets(0.0, 0.0);
}

Robot::~Robot() = default;
const RobotConfig& Robot::config() const {
  return impl_->config;
}

void Robot::setWheelRateTargets(double left_radps, double right_radps) {
  // The hinge angle of B (wheel) about A's +y axis grows when the wheel rolls backwards.
  impl_->hinge_left->enableAngularMotor(true, -left_radps,
                                        impl_->config.max_wheel_torque_nm * impl_->motor_dt_s);
  impl_->hinge_right->enableAngularMotor(true, -right_radps,
                                         impl_->config.max_wheel_torque_nm * impl_->motor_dt_s);
}

void Robot::setWheelFriction(double left, double right) {
  impl_->wheel_left.body->setFriction(left);
  impl_->wheel_right.body->setFriction(right);
}

void Robot::setHeld(bool held) {
  Impl& m = *impl_;
  if (held == m.held) return;
  m.held = held;
  btRigidBody& chassis = *m.chassis.body;
  // Bullet files a body as static or dynamic when it is added: remove, change, add again.
  m.scene.dynamics().removeRigidBody(&chassis);
  btVector3 inertia(0, 0, 0);
  if (!held) chassis.getCollisionShape()->calculateLocalInertia(m.config.chassis_mass_kg, inertia);
  chassis.setMassProps(held ? 0.0 : m.config.chassis_mass_kg, inertia);
  chassis.updateInertiaTensor();
  chassis.setLinearVelocity(btVector3(0, 0, 0));
  chassis.setAngularVelocity(btVector3(0, 0, 0));
  m.scene.dynamics().addRigidBody(&chassis, kRobotGroup, m.chassis_mask);
  chassis.forceActivationState(DISABLE_DEACTIVATION);
  // The body stops (or starts) at once: what is left of the wheels' motion is their spin.
  const btVector3 axle = chassis.getWorldTransform().getBasis().getColumn(1);
  for (Body* b : {&m.wheel_left, &m.wheel_right, &m.caster_front, &m.caster_back}) {
    if (!b->body) continue;
    const bool wheel = b == &m.wheel_left || b == &m.wheel_right;
    b->body->setLinearVelocity(btVector3(0, 0, 0));
    b->body->setAngularVelocity(wheel ? axle * b->body->getAngularVelocity().dot(axle)
                                      : btVector3(0, 0, 0));
  }
}

bool Robot::held() const {
  return impl_->held;
}

void Robot::update() {
  Impl& m = *impl_;
  const double dt_s = m.scene.time_s() - m.last_time_s;
  m.last_time_s = m.scene.time_s();
  if (dt_s > 0 && std::abs(dt_s - m.motor_dt_s) > 1e-12) m.setMotorLimit(dt_s);
  m.angle_left.update(m.hingeAngle(*m.hinge_left));
  m.angle_right.update(m.hingeAngle(*m.hinge_right));
}

SE2 Robot::T_world_base() const {
  // From the wheel centres, not the chassis: the hinges let the chassis trail the wheels by
  // about v * dt while accelerating (measured 0.9 mm at 1 m/s, 1 kHz), and the base frame is
  // defined by the wheels.
  const btVector3 left = impl_->wheel_left.body->getWorldTransform().getOrigin();
  const btVector3 right = impl_->wheel_right.body->getWorldTransform().getOrigin();
  const btVector3 mid = (left + right) / 2;
  const btVector3 y_axis = left - right;  // base y axis: from the right wheel to the left wheel
  return {mid.x(), mid.y(), std::atan2(-y_axis.x(), y_axis.y())};
}

double Robot::tilt_rad() const {
  const btVector3 z = impl_->chassis.body->getWorldTransform().getBasis().getColumn(2);
  return std::acos(std::clamp(z.z(), -1.0, 1.0));
}

double Robot::baseHeight_m() const {
  const DiffDriveParams& g = impl_->config.geometry;
  const double left = impl_->wheel_left.body->getWorldTransform().getOrigin().z() - g.radius_left_m;
  const double right =
      impl_->wheel_right.body->getWorldTransform().getOrigin().z() - g.radius_right_m;
  return (left + right) / 2;
}

double Robot::wheelAngleLeft() const {
  return impl_->angle_left.total_rad;
}
double Robot::wheelAngleRight() const {
  return impl_->angle_right.total_rad;
}

Eigen::Vector2d Robot::linearVelocity_world() const {
  // The base origin lies under the midpoint of the wheel centres.
  const btVector3 v =
      (impl_->wheel_left.body->getLinearVelocity() + impl_->wheel_right.body->getLinearVelocity()) /
      2;
  return {v.x(), v.y()};
}

double Robot::yawRate() const {
  // Of the axle line through the wheel centres, like T_world_base().
  const btRigidBody& left = *impl_->wheel_left.body;
  const btRigidBody& right = *impl_->wheel_right.body;
  const btVector3 axle =
      left.getWorldTransform().getOrigin() - right.getWorldTransform().getOrigin();
  const btVector3 dv = left.getLinearVelocity() - right.getLinearVelocity();
  // d/dt of the axle's direction angle: (axle x dv).z / |axle_xy|^2.
  return (axle.x() * dv.y() - axle.y() * dv.x()) / (axle.x() * axle.x() + axle.y() * axle.y());
}

namespace {
/// Wheel spin relative to the chassis about the chassis +y axis, positive forward.
double relativeSpin(const btRigidBody& chassis, const btRigidBody& wheel) {
  const btVector3 axis = chassis.getWorldTransform().getBasis().getColumn(1);
  return (wheel.getAngularVelocity() - chassis.getAngularVelocity()).dot(axis);
}
}  // namespace

double Robot::wheelRateLeft() const {
  return relativeSpin(*impl_->chassis.body, *impl_->wheel_left.body);
}
double Robot::wheelRateRight() const {
  return relativeSpin(*impl_->chassis.body, *impl_->wheel_right.body);
}

}  // namespace slamprep::sim
