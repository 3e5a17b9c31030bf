#include "slamprep/sim/physics/scene.hpp"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

namespace slamprep::sim {
namespace {

btVector3 at(const Eigen::Vector2d& p, double z) {
  return {p.x(), p.y(), z};
}

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// The vertices counter-clockwise (positive shoelace area).
std::vector<Eigen::Vector2d> counterClockwise(std::vector<Eigen::Vector2d> v) {
  double area2 = 0.0;
  for (std::size_t i = 0; i < v.size(); ++i) area2 += cross(v[i], v[(i + 1) % v.size()]);
  if (area2 < 0) std::reverse(v.begin(), v.end());
  return v;
}

/// True when p lies inside or on triangle (a, b, c), counter-clockwise.
bool inTriangle(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                const Eigen::Vector2d& c) {
  return cross(b - a, p - a) >= 0 && cross(c - b, p - b) >= 0 && cross(a - c, p - c) >= 0;
}

/// Ear clipping of a simple counter-clockwise polygon: n - 2 triangles as index triples.
std::vector<std::array<std::size_t, 3>> triangulate(const std::vector<Eigen::Vector2d>& v) {
  std::vector<std::size_t> ring(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) ring[i] = i;
  std::vector<std::array<std::size_t, 3>> triangles;
  while (ring.size() > 3) {
    bool clipped = false;
    for (std::size_t k = 0; k < ring.size() && !clipped; ++k) {
      const std::size_t a = ring[(k + ring.size() - 1) % ring.size()], b = ring[k],
                        c = ring[(k + 1) % ring.size()];
      if (cross(v[b] - v[a], v[c] - v[b]) <= 0) continue;  // reflex or flat corner: no ear
      bool empty = true;
      for (std::size_t j : ring)
        if (j != a && j != b && j != c && inTriangle(v[j], v[a], v[b], v[c])) empty = false;
      if (!empty) continue;
      triangles.push_back({a, b, c});
      ring.erase(ring.begin() + static_cast<std::ptrdiff_t>(k));
      clipped = true;
    }
    if (!clipped) break;  // only flat corners left (validated input has none): stop
  }
  if (ring.size() == 3) triangles.push_back({ring[0], ring[1], ring[2]});
  return triangles;
}

/// Adds a vertical prism (side walls and top cap) over a simple outline to the mesh.
void addPrismTriangles(btTriangleMesh& mesh, const std::vector<Eigen::Vector2d>& outline,
                       double height) {
  const std::vector<Eigen::Vector2d> v = counterClockwise(outline);
  for (std::size_t i = 0; i < v.size(); ++i) {
    const Eigen::Vector2d& p = v[i];
    const Eigen::Vector2d& q = v[(i + 1) % v.size()];
    mesh.addTriangle(at(p, 0.0), at(q, 0.0), at(q, height));
    mesh.addTriangle(at(p, 0.0), at(q, height), at(p, height));
  }
  for (const auto& t : triangulate(v))
    mesh.addTriangle(at(v[t[0]], height), at(v[t[1]], height), at(v[t[2]], height));
}

/// Squared distance from p to segment a-b.
double squaredDistanceToSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a,
                                const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double t = std::clamp((p - a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
  return (a + t * ab - p).squaredNorm();
}

/// True when the disc (p, r) overlaps the closed simple polygon v.
bool discOverlapsPolygon(const Eigen::Vector2d& p, double r,
                         const std::vector<Eigen::Vector2d>& v) {
  bool inside = false;  // even-odd crossing rule
  for (std::size_t i = 0, j = v.size() - 1; i < v.size(); j = i++) {
    if (squaredDistanceToSegment(p, v[j], v[i]) < r * r) return true;
    if ((v[i].y() > p.y()) != (v[j].y() > p.y()) &&
        p.x() < v[j].x() + (p.y() - v[j].y()) * (v[i].x() - v[j].x()) / (v[i].y() - v[j].y()))
      inside = !inside;
  }
  return inside;
}

/// Exact ray-circle distance: smallest t >= 0 with |o + t d - c| = r, d a unit vector.
std::optional<double> rayCircle(const Eigen::Vector2d& o, const Eigen::Vector2d& d,
                                const Eigen::Vector2d& c, double r) {
  const Eigen::Vector2d oc = o - c;
  const double b = oc.dot(d);
  const double disc = b * b - (oc.squaredNorm() - r * r);
  if (disc < 0) return std::nullopt;
  const double t = -b - std::sqrt(disc);  // Eq.: t^2 + 2 b t + |oc|^2 - r^2 = 0
  if (t < 0) return std::nullopt;
  return t;
}

/// Closest-hit callback that also remembers the user index of the object hit (cylinder index).
struct ClosestObjectCallback : btCollisionWorld::ClosestRayResultCallback {
  using ClosestRayResultCallback::ClosestRayResultCallback;
  int cylinder = -1;  ///< index into World::cylinders, -1 for a mesh
  btScalar addSingleResult(btCollisionWorld::LocalRayResult& result,
                           bool normal_in_world) override {
    cylinder = result.m_collisionObject->getUserIndex();
    return ClosestRayResultCallback::addSingleResult(result, normal_in_world);
  }
};

/// btDiscreteDynamicsWorld without the per-step motion prediction for continuous collision
/// detection when no body uses it (ccd motion threshold 0, the default): Bullet's own
/// createPredictiveContacts then integrates every body once more and creates nothing.
class FixedStepWorld : public btDiscreteDynamicsWorld {
 public:
  using btDiscreteDynamicsWorld::btDiscreteDynamicsWorld;

 protected:
  void createPredictiveContacts(btScalar dt_s) override {
    for (int i = 0; i < m_nonStaticRigidBodies.size(); ++i) {
      if (m_nonStaticRigidBodies[i]->getCcdSquareMotionThreshold() != 0) {
        btDiscreteDynamicsWorld::createPredictiveContacts(dt_s);
        return;
      }
    }
    releasePredictiveContacts();
    for (int i = 0; i < m_nonStaticRigidBodies.size(); ++i)
      m_nonStaticRigidBodies[i]->setHitFraction(1.0);  // as Bullet does
  }
};

/// Collision configuration with small memory pools: Bullet's default 4096-entry pools cost
/// ~10 ms to set up per Scene and this world holds a handful of contact pairs (the pools fall
/// back to the heap when full).
btDefaultCollisionConstructionInfo smallPools() {
  btDefaultCollisionConstructionInfo info;
  info.m_defaultMaxPersistentManifoldPoolSize = 64;
  info.m_defaultMaxCollisionAlgorithmPoolSize = 64;
  return info;
}

}  // namespace

struct Scene::Impl {
  World world;
  PlanarCaster caster;
  btDefaultCollisionConfiguration config{smallPools()};
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  FixedStepWorld dynamics{&dispatcher, &broadphase, &solver, &config};

  btStaticPlaneShape floor_shape{btVector3(0, 0, 1), 0.0};
  btCollisionObject floor;
  /// Every wall, box, polygon and cylinder is its own collision object, so the broadphase pairs
  /// a robot only with the objects near it (a single compound spanning the room overlaps every
  /// body and its children had to be walked every step).
  std::vector<std::unique_ptr<btTriangleMesh>> meshes;
  std::vector<std::unique_ptr<btCollisionShape>> shapes;
  std::vector<std::unique_ptr<btCollisionObject>> statics;
  double time_s = 0.0;

  Impl(const World& w, const ScenePhysicsParams& params);
  ~Impl();
  void addStatic(std::unique_ptr<btCollisionShape> shape, const btTransform& pose, int cylinder);
  void addPrism(const std::vector<Eigen::Vector2d>& outline, double height_m);
};

void Scene::Impl::addStatic(std::unique_ptr<btCollisionShape> shape, const btTransform& pose,
                            int cylinder) {
  auto object = std::make_unique<btCollisionObject>();
  object->setCollisionShape(shape.get());
  object->setWorldTransform(pose);
  object->setFriction(0.5);
  object->setUserIndex(cylinder);
  // Never moves: with setForceUpdateAllAabbs(false) Bullet skips its AABB every step.
  object->setActivationState(ISLAND_SLEEPING);
  // Robots and rays see static objects; static objects and the floor never pair up.
  dynamics.addCollisionObject(object.get(), kStaticGroup,
                              btBroadphaseProxy::AllFilter ^ kStaticGroup);
  shapes.push_back(std::move(shape));
  statics.push_back(std::move(object));
}

void Scene::Impl::addPrism(const std::vector<Eigen::Vector2d>& outline, double height_m) {
  // A triangle mesh: its ray test is an exact ray-triangle intersection.
  meshes.push_back(std::make_unique<btTriangleMesh>(true, false));  // 32-bit indices, 3 floats
  addPrismTriangles(*meshes.back(), outline, height_m);
  addStatic(std::make_unique<btBvhTriangleMeshShape>(meshes.back().get(), true),
            btTransform::getIdentity(), -1);
}

Scene::Impl::Impl(const World& w, const ScenePhysicsParams& params) : world(w), caster(w) {
  assert(params.solver_iterations > 0 && params.contact_relaxation > 0 &&
         params.contact_relaxation < 2);
  dynamics.setGravity(btVector3(0, 0, -9.81));
  dynamics.setForceUpdateAllAabbs(false);  // only active (robot) bodies move
  btContactSolverInfo& solver_info = dynamics.getSolverInfo();
  solver_info.m_numIterations = params.solver_iterations;
  solver_info.m_sor = params.contact_relaxation;

  floor.setCollisionShape(&floor_shape);
  floor.setFriction(1.0);
  floor.setRollingFriction(0.0);
  floor.setActivationState(ISLAND_SLEEPING);
  dynamics.addCollisionObject(&floor, kFloorGroup,
                              btBroadphaseProxy::AllFilter ^ (kStaticGroup | kFloorGroup));

  for (const Wall& wall : world.walls) addPrism(footprint(wall), wall.height_m);
  for (const Box& box : world.boxes) addPrism(footprint(box), box.height_m);
  for (const Polygon& poly : world.polygons) addPrism(poly.vertices_m, poly.height_m);
  // Cylinders stay exact primitives (btCylinderShapeZ); Bullet's ray test against them is
  // iterative, so castRayBullet refines their hits analytically.
  for (std::size_t i = 0; i < world.cylinders.size(); ++i) {
    const Cylinder& cyl = world.cylinders[i];
    const double h = cyl.height_m / 2;
    btTransform pose = btTransform::getIdentity();
    pose.setOrigin(at(cyl.center_m, h));
    addStatic(std::make_unique<btCylinderShapeZ>(btVector3(cyl.radius_m, cyl.radius_m, h)), pose,
              static_cast<int>(i));
  }
  dynamics.updateAabbs();
}

Scene::Impl::~Impl() {
  for (auto& object : statics) dynamics.removeCollisionObject(object.get());
  dynamics.removeCollisionObject(&floor);
}

Scene::Scene(const World& world, const ScenePhysicsParams& params)
    : impl_(std::make_unique<Impl>(world, params)) {}
Scene::~Scene() = default;
btDiscreteDynamicsWorld& Scene::dynamics() {
  return impl_->dynamics;
}
const btDiscreteDynamicsWorld& Scene::dynamics() const {
  return impl_->dynamics;
}
const World& Scene::world() const {
  return impl_->world;
}
double Scene::time_s() const {
  return impl_->time_s;
}

void Scene::step(double dt_s) {
  assert(dt_s > 0);
  impl_->dynamics.stepSimulation(dt_s, 0);
  impl_->time_s += dt_s;
}

std::optional<double> Scene::castRay(const Eigen::Vector2d& origin_m, double yaw_rad,
                                     double height_m, double max_range_m) const {
  return castRay(origin_m, Eigen::Vector2d(std::cos(yaw_rad), std::sin(yaw_rad)), height_m,
                 max_range_m);
}

std::optional<double> Scene::castRay(const Eigen::Vector2d& origin_m, const Eigen::Vector2d& dir,
                                     double height_m, double max_range_m) const {
  return impl_->caster.cast(origin_m, dir, height_m, max_range_m);
}

std::optional<double> Scene::castRayBullet(const Eigen::Vector2d& origin_m, double yaw_rad,
                                           double height_m, double max_range_m) const {
  assert(max_range_m > 0);
  const Eigen::Vector2d dir(std::cos(yaw_rad), std::sin(yaw_rad));
  const btVector3 from = at(origin_m, height_m);
  const btVector3 to = at(origin_m + max_range_m * dir, height_m);
  ClosestObjectCallback callback(from, to);
  callback.m_collisionFilterMask = kStaticGroup;  // static geometry only: no floor, no robots
  impl_->dynamics.rayTest(from, to, callback);
  if (!callback.hasHit()) return std::nullopt;
  double range_m = callback.m_closestHitFraction * max_range_m;
  if (callback.cylinder >= 0) {
    // Bullet's convex cast against a cylinder is iterative (~1e-5 m): refine it exactly.
    const Cylinder& c = impl_->world.cylinders[static_cast<std::size_t>(callback.cylinder)];
    if (const auto exact = rayCircle(origin_m, dir, c.center_m, c.radius_m)) range_m = *exact;
  }
  if (range_m > max_range_m) return std::nullopt;
  return range_m;
}

bool Scene::collides(const Eigen::Vector2d& p_world_m, double radius_m) const {
  const World& w = impl_->world;
  for (const Cylinder& c : w.cylinders)
    if ((p_world_m - c.center_m).norm() < radius_m + c.radius_m) return true;
  for (const Wall& wall : w.walls)
    if (discOverlapsPolygon(p_world_m, radius_m, footprint(wall))) return true;
  for (const Box& box : w.boxes)
    if (discOverlapsPolygon(p_world_m, radius_m, footprint(box))) return true;
  for (const Polygon& poly : w.polygons)
    if (discOverlapsPolygon(p_world_m, radius_m, poly.vertices_m)) return true;
  return false;
}

}  // namespace slamprep::sim
