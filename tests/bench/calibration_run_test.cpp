// The interval policy `slamprep calibrate` (calibrateDataset) and the bench (calibrationMotion
// with default options) share: the same log gives both the same intervals, one per scan match.
#include "eval/bench/calibration_run.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "eval/formats/dataset_io.hpp"
#include "sim/drive/simulator.hpp"
#include "tests/support/scratch_dir.hpp"

namespace slamprep::eval {
namespace {

TEST(CalibrationRun, CalibrateAndBenchCutTheSameIntervals) {
  sim::SimConfig config;  // default world and scenario: figure eight first
  config.mode = sim::SimMode::kinematic;
  config.duration_s = 4.0;
  const test::ScratchDir scratch("calibration_run");
  const auto dir = scratch / "data";
  writeDataset(dir, sim::simulate(config).dataset);

  DatasetCalibrationParams params;  // what `slamprep calibrate DIR --method joint` runs
  params.dataset = dir.string();
  params.methods = {algo::CalibrationMethod::kJoint};
  const DatasetCalibration c = calibrateDataset(params);
  const CalibrationMotion bench = calibrationMotion(readDataset(dir), {});  // the bench's call

  ASSERT_EQ(c.intervals.intervals.size(), bench.intervals.intervals.size());
  for (std::size_t i = 0; i < bench.intervals.intervals.size(); ++i) {
    EXPECT_EQ(c.intervals.intervals[i].t_start_s, bench.intervals.intervals[i].t_start_s);
    EXPECT_EQ(c.intervals.intervals[i].t_end_s, bench.intervals.intervals[i].t_end_s);
  }
  // One interval per converged match, unless the robot stood still over it.
  int converged = 0;
  for (const algo::ScanMatch& m : bench.matches) converged += m.match.converged ? 1 : 0;
  EXPECT_EQ(static_cast<int>(bench.intervals.intervals.size()) +
                bench.intervals.dropped_standstill + bench.intervals.dropped_uncovered,
            converged);
  EXPECT_GT(bench.intervals.intervals.size(), 30u);
}

}  // namespace
}  // namespace slamprep::eval
