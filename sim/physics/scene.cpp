#include "sim/physics/scene.hpp"

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
void addPrism(btTriangleMesh& mesh, const std::vector<Eigen::Vector2d>& outline, double height) {
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

/// Closest-hit callback that also remembers which compound child was hit.
struct ClosestChildCallback : btCollisionWorld::ClosestRayResultCallback {
  using ClosestRayResultCallback::ClosestRayResultCallback;
  int child = -1;  ///< compound child index for convex children, -1 for the mesh
  btScalar addSingleResult(btCollisionWorld::LocalRayResult& result,
                           bool normal_in_world) override {
    const auto* info = result.m_localShapeInfo;
    child = (info && info->m_shapePart == -1) ? info->m_triangleIndex : -1;
    return ClosestRayResultCallback::addSingleResult(result, normal_in_world);
  }
};

}  // namespace

struct Scene::Impl {
  World world;
  btDefaultCollisionConfiguration config;
  btCollisionDispatcher dispatcher{&config};
  btDbvtBroadphase broadphase;
  btSequentialImpulseConstraintSolver solver;
  btDiscreteDynamicsWorld dynamics{&dispatcher, &broadphase, &solver, &config};

  btStaticPlaneShape floor_shape{btVector3(0, 0, 1), 0.0};
  btCollisionObject floor;
  btTriangleMesh mesh{true, false};  // 32-bit indices, 3-component vertices
  std::unique_ptr<btBvhTriangleMeshShape> mesh_shape;
  std::vector<std::unique_ptr<btCylinderShapeZ>> cylinder_shapes;
  btCompoundShape static_shape{true, 0};
  btCollisionObject statics;
  int first_cylinder_child = 0;
  double time_s = 0.0;

  explicit Impl(const World& w);
  ~Impl();
};

Scene::Impl::Impl(const World& w) : world(w) {
  dynamics.setGravity(btVector3(0, 0, -9.81));
  dynamics.getSolverInfo().m_numIterations = 50;

  floor.setCollisionShape(&floor_shape);
  floor.setFriction(1.0);
  floor.setRollingFriction(0.0);
  dynamics.addCollisionObject(&floor, kFloorGroup, btBroadphaseProxy::AllFilter);

  // Walls, boxes and polygons become one triangle mesh: its ray test is an exact ray-triangle
  // intersection. Cylinders stay exact primitives (btCylinderShapeZ) and are refined analytically.
  for (const Wall& wall : world.walls) addPrism(mesh, footprint(wall), wall.height_m);
  for (const Box& box : world.boxes) addPrism(mesh, footprint(box), box.height_m);
  for (const Polygon& poly : world.polygons) addPrism(mesh, poly.vertices_m, poly.height_m);
  btTransform identity = btTransform::getIdentity();
  if (mesh.getNumTriangles() > 0) {
    mesh_shape = std::make_unique<btBvhTriangleMeshShape>(&mesh, true);
    static_shape.addChildShape(identity, mesh_shape.get());
  }
  first_cylinder_child = static_shape.getNumChildShapes();
  for (const Cylinder& cyl : world.cylinders) {
    const double h = cyl.height_m / 2;
    cylinder_shapes.push_back(
        std::make_unique<btCylinderShapeZ>(btVector3(cyl.radius_m, cyl.radius_m, h)));
    btTransform pose = identity;
    pose.setOrigin(at(cyl.center_m, h));
    static_shape.addChildShape(pose, cylinder_shapes.back().get());
  }
  statics.setCollisionShape(&static_shape);
  statics.setFriction(0.5);
  dynamics.addCollisionObject(&statics, kStaticGroup, btBroadphaseProxy::AllFilter);
  dynamics.updateAabbs();
}

Scene::Impl::~Impl() {
  dynamics.removeCollisionObject(&statics);
  dynamics.removeCollisionObject(&floor);
}

Scene::Scene(const World& world) : impl_(std::make_unique<Impl>(world)) {}
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
  assert(max_range_m > 0);
  const Eigen::Vector2d dir(std::cos(yaw_rad), std::sin(yaw_rad));
  const btVector3 from = at(origin_m, height_m);
  const btVector3 to = at(origin_m + max_range_m * dir, height_m);
  ClosestChildCallback callback(from, to);
  // Fast path: test the one static object directly, skipping the broadphase (robots ignored).
  btTransform from_pose = btTransform::getIdentity(), to_pose = btTransform::getIdentity();
  from_pose.setOrigin(from);
  to_pose.setOrigin(to);
  const btCollisionObject& statics = impl_->statics;
  btCollisionWorld::rayTestSingle(from_pose, to_pose, const_cast<btCollisionObject*>(&statics),
                                  &impl_->static_shape, statics.getWorldTransform(), callback);
  if (!callback.hasHit()) return std::nullopt;
  double range_m = callback.m_closestHitFraction * max_range_m;
  const int cyl = callback.child - impl_->first_cylinder_child;
  if (callback.child >= 0 && cyl >= 0) {
    // Bullet's convex cast against a cylinder is iterative (~1e-5 m): refine it exactly.
    const Cylinder& c = impl_->world.cylinders[static_cast<std::size_t>(cyl)];
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
