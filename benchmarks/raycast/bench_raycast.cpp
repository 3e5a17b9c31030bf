// Ray-cast speed in room.yaml: the harness' Lidar::measure over full 720-beam scans against bare
// btCollisionWorld::rayTest with ClosestRayResultCallback over the SAME rays (same origins,
// directions, height and range). Goal: harness time <= 1.3 x bare rayTest. The harness casts
// through PlanarCaster (exact 2D caster over the static prisms); Scene::castRayBullet, the
// Bullet reference it is tested against, is timed too.
// Run: bench_raycast [--benchmark_out=results.json --benchmark_out_format=json]

#include <benchmark/benchmark.h>
#include <btBulletDynamicsCommon.h>

#include <numbers>
#include <vector>

#include "slamprep/sim/physics/lidar.hpp"

namespace slamprep::sim {
namespace {

constexpr int kPoses = 8;

/// The scene, the lidar, and 8 sensor poses on a 2.5 m circle around the room's start pose.
struct Setup {
  Scene scene{loadWorld(std::filesystem::path(SLAMPREP_SOURCE_DIR) / "worlds" / "room.yaml")};
  LidarConfig config;
  std::vector<SE2> T_world_lidar;

  Setup() {
    const SE2 start = scene.world().T_world_start;
    for (int k = 0; k < kPoses; ++k) {
      const double a = 2 * std::numbers::pi * k / kPoses;
      const SE2 T_world_base(start.x + 2.5 * std::cos(a), start.y + 2.5 * std::sin(a), 0.3 * k);
      T_world_lidar.push_back(T_world_base * config.T_base_lidar);
    }
  }

  /// The rays Lidar::measure casts: (from, to) for every beam of every pose.
  std::vector<std::pair<btVector3, btVector3>> rays() const {
    const Lidar lidar(config, 1);
    std::vector<std::pair<btVector3, btVector3>> out;
    for (const SE2& T : T_world_lidar)
      for (std::size_t i = 0; i < lidar.beamsPerScan(); ++i) {
        const double yaw = T.yaw + lidar.beamAngle(i);
        const btVector3 from(T.x, T.y, config.height_m);
        const btVector3 dir(std::cos(yaw), std::sin(yaw), 0.0);
        out.emplace_back(from, from + config.range_max_m * dir);
      }
    return out;
  }
};

Setup& setup() {
  static Setup s;
  return s;
}

void BM_HarnessLidarMeasure(benchmark::State& state) {
  Setup& s = setup();
  Lidar lidar(s.config, 7);
  for (auto _ : state)
    for (const SE2& T : s.T_world_lidar)
      for (std::size_t i = 0; i < lidar.beamsPerScan(); ++i)
        benchmark::DoNotOptimize(lidar.measure(s.scene, T, i));
  state.SetItemsProcessed(state.iterations() * kPoses *
                          static_cast<std::int64_t>(lidar.beamsPerScan()));
  state.counters["scans"] = benchmark::Counter(static_cast<double>(state.iterations() * kPoses),
                                               benchmark::Counter::kIsRate);
}

void BM_BareRayTest(benchmark::State& state) {
  Setup& s = setup();
  const auto rays = s.rays();
  const btCollisionWorld& world = s.scene.dynamics();
  for (auto _ : state)
    for (const auto& [from, to] : rays) {
      btCollisionWorld::ClosestRayResultCallback callback(from, to);
      world.rayTest(from, to, callback);
      benchmark::DoNotOptimize(callback.m_closestHitFraction);
    }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(rays.size()));
  state.counters["scans"] = benchmark::Counter(static_cast<double>(state.iterations() * kPoses),
                                               benchmark::Counter::kIsRate);
}

/// Scene::castRay alone (no noise, no Beam): the harness' ray path without the lidar.
void BM_SceneCastRay(benchmark::State& state) {
  Setup& s = setup();
  const Lidar lidar(s.config, 1);
  for (auto _ : state)
    for (const SE2& T : s.T_world_lidar)
      for (std::size_t i = 0; i < lidar.beamsPerScan(); ++i)
        benchmark::DoNotOptimize(s.scene.castRay(T.translation(), T.yaw + lidar.beamAngle(i),
                                                 s.config.height_m, s.config.range_max_m));
  state.SetItemsProcessed(state.iterations() * kPoses *
                          static_cast<std::int64_t>(lidar.beamsPerScan()));
}

/// Scene::castRayBullet: the Bullet reference of castRay (rayTest plus the cylinder refinement).
void BM_SceneCastRayBullet(benchmark::State& state) {
  Setup& s = setup();
  const Lidar lidar(s.config, 1);
  for (auto _ : state)
    for (const SE2& T : s.T_world_lidar)
      for (std::size_t i = 0; i < lidar.beamsPerScan(); ++i)
        benchmark::DoNotOptimize(s.scene.castRayBullet(T.translation(), T.yaw + lidar.beamAngle(i),
                                                       s.config.height_m, s.config.range_max_m));
  state.SetItemsProcessed(state.iterations() * kPoses *
                          static_cast<std::int64_t>(lidar.beamsPerScan()));
}

BENCHMARK(BM_HarnessLidarMeasure)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BareRayTest)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SceneCastRay)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SceneCastRayBullet)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace slamprep::sim

BENCHMARK_MAIN();
