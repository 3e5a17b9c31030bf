#include "sim/physics/robot.hpp"

namespace slamprep::sim {

struct Robot::Impl {
  RobotConfig config;
  SE2 T_world_base;
};

Robot::Robot(Scene&, const RobotConfig& config, const SE2& T_world_base0)
    : impl_(std::make_unique<Impl>()) {
  impl_->config = config;
  impl_->T_world_base = T_world_base0;
}
Robot::~Robot() = default;
const RobotConfig& Robot::config() const {
  return impl_->config;
}
void Robot::setWheelRateTargets(double, double) {}
void Robot::update() {}
SE2 Robot::T_world_base() const {
  return impl_->T_world_base;
}
double Robot::wheelAngleLeft() const {
  return 0.0;
}
double Robot::wheelAngleRight() const {
  return 0.0;
}
Eigen::Vector2d Robot::linearVelocity_world() const {
  return Eigen::Vector2d::Zero();
}
double Robot::yawRate() const {
  return 0.0;
}
double Robot::wheelRateLeft() const {
  return 0.0;
}
double Robot::wheelRateRight() const {
  return 0.0;
}

}  // namespace slamprep::sim
