// De-skew speed. Goal: every method other than vicp and odom-icp at least 20 million beams per
// second on one core (items_per_second below), repacking included. vicp and odom-icp run ICP
// against the previous scan and are reported per scan. Data: analytic room, 10 Hz, 720 beams,
// 1 cm noise, the 1 m/s, 1 rad/s arc; odometry at 100 Hz, IMU at 200 Hz.
#include <benchmark/benchmark.h>

#include "slamprep/algo/deskew/deskew.hpp"
#include "slamprep/tests/algo_deskew/synthetic_world.hpp"

namespace {

using namespace slamprep;
using namespace slamprep::testing;

struct Data {
  PoseSeries truth, odometry;
  ImuLog imu;
  std::vector<SyntheticScan> scans;
};

const Data& data() {
  static const Data d = [] {
    Data d;
    const Motion m{SE2(-0.5, -0.3, 0.2), 1.0, 1.0, 0.0, 0.0};
    d.truth = sampleTruth(m, 0.0, 3.0, 1e-3);
    d.odometry = resample(d.truth, 0.0, 3.0, 100.0);
    for (int k = 0; k <= 600; ++k) d.imu.push_back({k * 0.005, 1.0, 0.0, 0.0});
    std::mt19937 rng(1);
    LidarConfig cfg;
    cfg.range_noise_m = 0.01;
    for (int k = 0; k < 2; ++k)
      d.scans.push_back(
          castScan(roomWorld(), d.truth, SE2(0.1, 0.0, 0.0), 1.0 + 0.1 * k, cfg, &rng));
    return d;
  }();
  return d;
}

void BM_Deskew(benchmark::State& state, algo::DeskewMethod method) {
  const Data& d = data();
  algo::DeskewInputs in;
  in.odometry = d.odometry;
  in.groundtruth = d.truth;
  in.imu = d.imu;
  in.T_base_lidar = SE2(0.1, 0.0, 0.0);
  in.previous =
      algo::PreviousScan{d.scans[0].scan, false, Eigen::Vector3d(1.0, 0.0, 1.0), std::nullopt};
  const LaserScan& scan = d.scans[1].scan;
  std::size_t refused = 0;
  for (auto _ : state) {
    const algo::DeskewResult r = algo::deskew(method, scan, in, {});
    refused += !r.ok;
    benchmark::DoNotOptimize(r.p_ref.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(scan.size()));
  state.counters["refused"] = static_cast<double>(refused);
}

using algo::DeskewMethod;
BENCHMARK_CAPTURE(BM_Deskew, none, DeskewMethod::kNone);
BENCHMARK_CAPTURE(BM_Deskew, oracle, DeskewMethod::kOracle);
BENCHMARK_CAPTURE(BM_Deskew, const_velocity, DeskewMethod::kConstVelocity);
BENCHMARK_CAPTURE(BM_Deskew, odom_linear, DeskewMethod::kOdomLinear);
BENCHMARK_CAPTURE(BM_Deskew, odom_quadratic, DeskewMethod::kOdomQuadratic);
BENCHMARK_CAPTURE(BM_Deskew, imu, DeskewMethod::kImu);
BENCHMARK_CAPTURE(BM_Deskew, vicp, DeskewMethod::kVicp)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_Deskew, odom_icp, DeskewMethod::kOdomIcp)->Unit(benchmark::kMillisecond);

}  // namespace
