#include "slamprep/sim/physics/scene.hpp"

#include <btBulletDynamicsCommon.h>
#include <gtest/gtest.h>

#include <numbers>
#include <random>

#include "slamprep/sim/physics/robot.hpp"
#include "slamprep/tests/sim_physics/box_room.hpp"
#include "test_util.hpp"

namespace slamprep::sim {
namespace {

using ::slamprep::test::boxRoomDistance;

TEST(Scene, CastRayMatchesAnalyticBoxRoom) {
  const Scene scene(loadWorld(test::worldFile("box_room.yaml")));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ux(-2.5, 2.5), uy(-1.5, 1.5),
      ua(-std::numbers::pi, std::numbers::pi);
  double worst = 0.0;
  for (int k = 0; k < 2000; ++k) {
    const Eigen::Vector2d p(ux(rng), uy(rng));
    const double yaw = ua(rng);
    const auto range = scene.castRay(p, yaw, 0.25, 30.0);
    ASSERT_TRUE(range.has_value());
    worst = std::max(worst, std::abs(*range - boxRoomDistance(p, {std::cos(yaw), std::sin(yaw)})));
  }
  // Triangle-mesh ray test in double precision: rounding only (measured ~1e-15 m).
  EXPECT_LT(worst, 1e-9);
}

TEST(Scene, CastRayAgainstCylinderIsAnalytic) {
  World world;
  world.cylinders.push_back({{2.0, 1.0}, 0.35, 1.0});
  const Scene scene(world);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  double worst = 0.0;
  for (int k = 0; k < 1000; ++k) {
    const Eigen::Vector2d origin(-2.0 + u(rng), u(rng));
    // Aim at a point up to 0.9 r beside the axis; the exact hit is the nearer root of
    // |o + t d - c|^2 = r^2.
    const Eigen::Vector2d to_axis = world.cylinders[0].center_m - origin;
    const Eigen::Vector2d normal(-to_axis.y(), to_axis.x());
    const Eigen::Vector2d aim =
        world.cylinders[0].center_m + 0.9 * 0.35 * u(rng) * normal.normalized();
    const Eigen::Vector2d d = (aim - origin).normalized();
    const Eigen::Vector2d oc = origin - world.cylinders[0].center_m;
    const double b = oc.dot(d);
    const double truth = -b - std::sqrt(b * b - oc.squaredNorm() + 0.35 * 0.35);
    const auto range = scene.castRay(origin, std::atan2(d.y(), d.x()), 0.5, 30.0);
    ASSERT_TRUE(range.has_value());
    worst = std::max(worst, std::abs(*range - truth));
  }
  EXPECT_LT(worst, 1e-9);  // refined analytically; Bullet's convex cast alone is ~1e-5 m off
  // Beside the cylinder, over it, and short of it: no return.
  EXPECT_FALSE(scene.castRay({0.0, 1.5}, 0.0, 0.5, 30.0).has_value());
  EXPECT_FALSE(scene.castRay({0.0, 1.0}, 0.0, 1.2, 30.0).has_value());
  EXPECT_FALSE(scene.castRay({0.0, 1.0}, 0.0, 0.5, 1.6).has_value());
  EXPECT_NEAR(*scene.castRay({0.0, 1.0}, 0.0, 0.5, 1.7), 1.65, 1e-12);
}

TEST(Scene, CastRayAgainstRotatedBoxAndNonConvexPolygon) {
  World world;
  world.boxes.push_back({SE2(0.0, 0.0, std::numbers::pi / 4), {2.0, 1.0}, 0.5});
  // An L: the notch's inner corner is at (6, 1).
  world.polygons.push_back({{{5, 0}, {8, 0}, {8, 3}, {7, 3}, {7, 1}, {5, 1}}, 1.0});
  const Scene scene(world);
  // Along the box's x axis from 3 m away: hits the end face at half length 1.0.
  EXPECT_NEAR(
      *scene.castRay({-3 / std::sqrt(2.0), -3 / std::sqrt(2.0)}, std::numbers::pi / 4, 0.3, 30.0),
      2.0, 1e-12);
  // Over the box (0.5 m tall): nothing.
  EXPECT_FALSE(scene.castRay({-3.0, -3.0}, std::numbers::pi / 4, 0.6, 30.0).has_value());
  // Down into the notch of the L from above its top: hits y = 1 at x = 6.
  EXPECT_NEAR(*scene.castRay({6.0, 5.0}, -std::numbers::pi / 2, 0.5, 30.0), 4.0, 1e-12);
  // Horizontally into the notch: the inner face x = 7.
  EXPECT_NEAR(*scene.castRay({5.5, 2.0}, 0.0, 0.5, 30.0), 1.5, 1e-12);
}

TEST(Scene, CastRayIgnoresRobots) {
  Scene scene(loadWorld(test::worldFile("box_room.yaml")));
  Robot robot(scene, RobotConfig{}, SE2(1.0, 0.0, 0.0));
  for (int k = 0; k < 10; ++k) scene.step(0.001);
  // The robot's chassis stands in the way of a ray along y = 0 at 0.1 m height...
  const btVector3 from(-2.0, 0.0, 0.1), to(2.9, 0.0, 0.1);
  btCollisionWorld::ClosestRayResultCallback all(from, to);
  scene.dynamics().rayTest(from, to, all);
  ASSERT_TRUE(all.hasHit());
  EXPECT_NEAR(all.m_hitPointWorld.x(), 1.0 - 0.2, 1e-3);  // chassis rear face
  // ...but castRay only sees the wall at x = 3.
  EXPECT_NEAR(*scene.castRay({-2.0, 0.0}, 0.0, 0.1, 30.0), 5.0, 1e-12);
}

TEST(Scene, CollidesIsExactIn2d) {
  World world = loadWorld(test::worldFile("box_room.yaml"));
  world.cylinders.push_back({{1.0, 1.0}, 0.2, 0.5});
  world.polygons.push_back({{{-2, -1}, {-1, -1}, {-1, 0}, {-1.5, -0.5}, {-2, 0}}, 0.5});
  const Scene scene(world);
  EXPECT_FALSE(scene.collides({0.0, 0.0}, 0.5));
  EXPECT_FALSE(scene.collides({2.69, 0.0}, 0.3));  // 0.01 m short of the wall x = 3
  EXPECT_TRUE(scene.collides({2.71, 0.0}, 0.3));
  EXPECT_FALSE(scene.collides({1.0, 1.5}, 0.29));  // 0.01 m short of the cylinder
  EXPECT_TRUE(scene.collides({1.0, 1.5}, 0.31));
  EXPECT_TRUE(scene.collides({-1.5, -0.8}, 0.01));  // inside the polygon
  // In the polygon's notch (reflex vertex at (-1.5, -0.5)): clear with a small disc.
  EXPECT_FALSE(scene.collides({-1.5, -0.3}, 0.1));
  EXPECT_TRUE(scene.collides({-1.5, -0.3}, 0.25));
}

}  // namespace
}  // namespace slamprep::sim
