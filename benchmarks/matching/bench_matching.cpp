// Scan matching speed. Goal: point-to-line ICP on 720-beam scans at most 0.5 ms median per scan
// pair on one core, everything included (kd-tree and line fits of the reference, the iterations).
// Data: analytic room (tests/algo_deskew/synthetic_world.hpp), consecutive scans of the 1 m/s,
// 1 rad/s arc at 10 Hz (10 cm, 0.1 rad apart), 1 cm range noise, guess = identity.
// Run: bench_matching --benchmark_repetitions=10 (the median is among the aggregates).
#include <benchmark/benchmark.h>

#include "slamprep/algo/matching/icp.hpp"
#include "slamprep/tests/algo_deskew/synthetic_world.hpp"

namespace {

using namespace slamprep;
using namespace slamprep::testing;

struct Pairs {
  std::vector<Points2> scans;
};

const Pairs& pairs() {
  static const Pairs p = [] {
    Pairs p;
    const Motion m{SE2(-0.5, -0.3, 0.2), 1.0, 1.0, 0.0, 0.0};
    const PoseSeries truth = sampleTruth(m, 0.0, 3.0, 1e-3);
    std::mt19937 rng(1);
    LidarConfig cfg;
    cfg.range_noise_m = 0.01;
    // Static scans (as if de-skewed) from the poses the arc passes every 100 ms.
    PoseSeries still;
    for (int k = 0; k < 21; ++k) {
      PoseSeries at;
      at.push_back(0.0, *truth.at(1.0 + 0.1 * k));
      at.push_back(1.0, *truth.at(1.0 + 0.1 * k));
      p.scans.push_back(castScan(roomWorld(), at, SE2(), 0.0, cfg, &rng).scan.points());
    }
    return p;
  }();
  return p;
}

void BM_PointToLine(benchmark::State& state) {
  const auto& scans = pairs().scans;
  std::size_t k = 0, failed = 0;
  for (auto _ : state) {
    const auto r = algo::matchPointToLine(scans[k], scans[k + 1], SE2(), {});
    failed += !r.converged;
    benchmark::DoNotOptimize(r.T_ref_cur);
    k = (k + 1) % (scans.size() - 1);
  }
  state.counters["failed"] = static_cast<double>(failed);
}
BENCHMARK(BM_PointToLine)->Unit(benchmark::kMillisecond);

void BM_PointToPoint(benchmark::State& state) {
  const auto& scans = pairs().scans;
  std::size_t k = 0;
  for (auto _ : state) {
    const auto r = algo::matchPointToPoint(scans[k], scans[k + 1], SE2(), {});
    benchmark::DoNotOptimize(r.T_ref_cur);
    k = (k + 1) % (scans.size() - 1);
  }
}
BENCHMARK(BM_PointToPoint)->Unit(benchmark::kMillisecond);

// The parts: reference preparation alone, and matching against a prepared reference.
void BM_PrepareReference(benchmark::State& state) {
  for (auto _ : state) {
    algo::IcpReference ref(pairs().scans[0], {}, true);
    benchmark::DoNotOptimize(ref.normal(0));
  }
}
BENCHMARK(BM_PrepareReference)->Unit(benchmark::kMicrosecond);

void BM_PointToLinePrepared(benchmark::State& state) {
  const algo::IcpReference ref(pairs().scans[0], {}, true);
  for (auto _ : state) {
    const auto r = algo::matchPointToLine(ref, pairs().scans[1], SE2(), {});
    benchmark::DoNotOptimize(r.T_ref_cur);
  }
}
BENCHMARK(BM_PointToLinePrepared)->Unit(benchmark::kMicrosecond);

}  // namespace
