// Simulator speed: room.yaml and the figure-eight scenario with the default configuration
// (1 kHz physics, 720-beam 10 Hz lidar, 100 Hz encoders, 200 Hz IMU) on one core.
// Goal: real-time factor >= 150 (simulated seconds per CPU second), memory reused between runs as
// in slamprep (core/freed_memory.hpp); ColdPages: each run on fresh pages.
// Counters: rtf = simulated seconds per CPU second; beams_per_s = lidar beams per CPU second;
// faults = page faults per run (each costs ~20 us on this project's VMs).
// Run: bench_sim [--benchmark_out=results.json --benchmark_out_format=json]

#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <filesystem>

#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "slamprep/core/freed_memory.hpp"
#include "slamprep/sim/drive/simulator.hpp"

namespace slamprep::sim {
namespace {

const std::filesystem::path kRoot(SLAMPREP_SOURCE_DIR);

struct Inputs {
  World world = loadWorld(kRoot / "worlds" / "room.yaml");
  Scenario scenario = loadScenario(kRoot / "worlds" / "scenarios" / "figure_eight.yaml");
};

const Inputs& inputs() {
  static const Inputs in;
  return in;
}

/// The allocator as slamprep's main() sets it: each run reuses the pages the last one freed.
/// BM_FigureEightPhysicsColdPages measures a run on fresh pages.
[[maybe_unused]] const bool kKeepFreedMemory = (keepFreedMemory(), true);

/// Minor page faults of the process so far.
double pageFaults() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_minflt);
}

/// Every run on fresh pages, as the only simulation of a process: the freed memory goes back to
/// the kernel between runs (outside the timing).
void returnFreedMemory(benchmark::State& state) {
  state.PauseTiming();
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
  state.ResumeTiming();
}

void runSimulation(benchmark::State& state, const SimConfig& config, bool cold_pages = false) {
  const Inputs& in = inputs();
  double sim_s = 0.0, beams = 0.0;
  const double faults_before = pageFaults();
  for (auto _ : state) {
    {
      const SimResult result = simulate(config, in.world, in.scenario);
      sim_s += result.summary.duration_s;
      beams += static_cast<double>(result.summary.beams);
      benchmark::DoNotOptimize(result.dataset.scans.data());
    }
    if (cold_pages) returnFreedMemory(state);
  }
  state.counters["rtf"] = benchmark::Counter(sim_s, benchmark::Counter::kIsRate);
  state.counters["beams_per_s"] = benchmark::Counter(beams, benchmark::Counter::kIsRate);
  state.counters["faults"] =
      benchmark::Counter(pageFaults() - faults_before, benchmark::Counter::kAvgIterations);
}

/// The goal: everything on, physics mode.
void BM_FigureEightPhysics(benchmark::State& state) {
  runSimulation(state, SimConfig{});
}

/// The same on fresh pages: what a single `slamprep simulate` pays.
void BM_FigureEightPhysicsColdPages(benchmark::State& state) {
  runSimulation(state, SimConfig{}, true);
}

/// Kinematic mode: no Bullet dynamics, the same ray casts.
void BM_FigureEightKinematic(benchmark::State& state) {
  SimConfig config;
  config.mode = SimMode::kinematic;
  runSimulation(state, config);
}

/// Physics with a one-beam lidar: the cost of dynamics, encoders, IMU and the loop alone.
void BM_FigureEightPhysicsNoLidar(benchmark::State& state) {
  SimConfig config;
  config.lidar.beams_per_revolution = 1;
  runSimulation(state, config);
}

/// Physics with the solver of the first version: 50 plain iterations, no over-relaxation.
void BM_FigureEightPhysicsSolver50(benchmark::State& state) {
  const Inputs& in = inputs();
  double sim_s = 0.0;
  for (auto _ : state) {
    const SimResult result = simulate(SimConfig{}, in.world, in.scenario, {}, {50, 1.0});
    sim_s += result.summary.duration_s;
    benchmark::DoNotOptimize(result.dataset.scans.data());
  }
  state.counters["rtf"] = benchmark::Counter(sim_s, benchmark::Counter::kIsRate);
}

BENCHMARK(BM_FigureEightPhysics)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FigureEightPhysicsColdPages)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FigureEightKinematic)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FigureEightPhysicsNoLidar)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FigureEightPhysicsSolver50)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace slamprep::sim

BENCHMARK_MAIN();
