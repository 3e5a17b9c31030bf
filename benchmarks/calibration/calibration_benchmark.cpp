// Speed of the calibration methods against the number of intervals (30 encoder steps each), on
// noisy synthetic data; the counters report the r_L error in ppm so accuracy is visible too.
#include <benchmark/benchmark.h>

#include <cmath>
#include <random>

#include "slamprep/algo/calibration/calibration.hpp"
#include "slamprep/core/odometry.hpp"

namespace {

using namespace slamprep;
using namespace slamprep::algo;

const DiffDriveParams kTruth{0.098, 0.102, 0.52};
const SE2 kMount{0.12, -0.04, 0.3};

std::vector<CalibrationInterval> makeIntervals(int n) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, 0.002);
  const Eigen::Vector2d patterns[4] = {{3.0, 6.0}, {6.0, 2.5}, {-4.0, 4.5}, {6.0, 6.5}};
  std::vector<CalibrationInterval> out;
  for (int k = 0; k < n; ++k) {
    CalibrationInterval in{0.3 * k, 0.3 * (k + 1), {}, {}};
    SE2 o;
    for (int j = 0; j < 30; ++j) {
      const Eigen::Vector2d w = (1.0 + 0.3 * std::sin(0.37 * j + 1.3 * k)) * patterns[k % 4];
      in.steps.push_back({0.01, 0.01 * w.x(), 0.01 * w.y()});
      o = o * wheelIncrement(kTruth, 0.01 * w.x(), 0.01 * w.y());
    }
    const SE2 sm = kMount.inverse() * o * kMount;
    in.T_lidarStart_lidarEnd = SE2(sm.x + noise(rng), sm.y + noise(rng), sm.yaw + noise(rng));
    out.push_back(std::move(in));
  }
  return out;
}

template <typename Method>
void run(benchmark::State& state, Method method) {
  const auto intervals = makeIntervals(static_cast<int>(state.range(0)));
  CalibrationResult result;
  for (auto _ : state) {
    result = method(intervals);
    benchmark::DoNotOptimize(result);
  }
  state.counters["r_L_error_ppm"] =
      1e6 * (result.geometry.radius_left_m / kTruth.radius_left_m - 1);
  state.counters["ok"] = result.ok;
}

void BM_ModelBased(benchmark::State& s) {
  run(s, [](const auto& in) { return calibrateModelBased(in); });
}
void BM_Joint(benchmark::State& s) {
  run(s, [](const auto& in) { return calibrateJoint(in); });
}
void BM_Ceres(benchmark::State& s) {
  run(s, [](const auto& in) { return calibrateCeres(in); });
}
void BM_CeresWithTimeOffset(benchmark::State& s) {
  CeresParams params;
  params.estimate_time_offset = true;
  run(s, [&](const auto& in) { return calibrateCeres(in, params); });
}

BENCHMARK(BM_ModelBased)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Joint)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_Ceres)->Arg(100)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CeresWithTimeOffset)->Arg(100)->Unit(benchmark::kMillisecond);

}  // namespace
