#include "sim/physics/scene.hpp"

#include <btBulletDynamicsCommon.h>

namespace slamprep::sim {

struct Scene::Impl {
  World world;
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld dynamics{&dispatcher, &broadphase, &solver, &config};
  double time_s = 0.0;
};

Scene::Scene(const World& world) : impl_(std::make_unique<Impl>()) {
  impl_->world = world;
}
Scene::~Scene() = default;
btDiscreteDynamicsWorld& Scene::dynamics() {
  return impl_->dynamics;
}
const btDiscreteDynamicsWorld& Scene::dynamics() const {
  return impl_->dynamics;
}
void Scene::step(double dt_s) {
  impl_->dynamics.stepSimulation(dt_s, 0);
  impl_->time_s += dt_s;
}
std::optional<double> Scene::castRay(const Eigen::Vector2d&, double, double, double) const {
  return std::nullopt;
}
bool Scene::collides(const Eigen::Vector2d&, double) const {
  return false;
}
const World& Scene::world() const {
  return impl_->world;
}
double Scene::time_s() const {
  return impl_->time_s;
}

}  // namespace slamprep::sim
