// Dataset write and read time for a 3-minute simulated run (docs/dataset.md "Sizes and speed"):
// 1800 scans x 720 beams with p_ref_true, 180 000 ground-truth poses, 18 000 encoder and
// 36 000 IMU samples.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <filesystem>

#include "slamprep/core/dataset.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/tests/formats_dataset/synthetic_dataset.hpp"

namespace slamprep {
namespace {

namespace fs = std::filesystem;

const Dataset& threeMinuteDataset() {
  static const Dataset d = [] {
    synthetic::SyntheticDatasetParams p;
    p.duration_s = 180.0;
    return synthetic::makeSyntheticDataset(p);
  }();
  return d;
}

fs::path benchDir() {
  return fs::temp_directory_path() / ("slamprep_formats_bench_" + std::to_string(::getpid()));
}

std::uintmax_t directoryBytes(const fs::path& dir) {
  std::uintmax_t bytes = 0;
  for (const auto& e : fs::directory_iterator(dir)) bytes += e.file_size();
  return bytes;
}

void BM_WriteDataset3min(benchmark::State& state) {
  const Dataset& d = threeMinuteDataset();
  const fs::path dir = benchDir();
  for (auto _ : state) eval::writeDataset(dir, d);
  state.counters["MB"] = directoryBytes(dir) / 1e6;
  fs::remove_all(dir);
}

void BM_ReadDataset3min(benchmark::State& state) {
  const fs::path dir = benchDir();
  eval::writeDataset(dir, threeMinuteDataset());
  std::size_t scans = 0;
  for (auto _ : state) {
    const Dataset back = eval::readDataset(dir);
    scans = back.scans.size();
    benchmark::DoNotOptimize(scans);
  }
  state.counters["scans"] = static_cast<double>(scans);
  state.counters["MB"] = directoryBytes(dir) / 1e6;
  fs::remove_all(dir);
}

BENCHMARK(BM_WriteDataset3min)->Unit(benchmark::kMillisecond)->Iterations(3);
BENCHMARK(BM_ReadDataset3min)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace
}  // namespace slamprep
