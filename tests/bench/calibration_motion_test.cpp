// `slamprep calibrate --stamp-is-last-beam`: the lidar motion calibration consumes is the same
// whether a scan's stamp marks its first beam or, said so, its last.
#include <gtest/gtest.h>

#include "eval/bench/calibration_run.hpp"
#include "sim/drive/simulator.hpp"

namespace slamprep::eval {
namespace {

/// The same dataset with every scan stamped at its last beam instead of its first.
Dataset stampedAtLastBeam(Dataset d) {
  for (ScanRecord& r : d.scans) r.scan.stamp_s = r.scan.endTime();
  return d;
}

void expectSameIntervals(const algo::IntervalSet& a, const algo::IntervalSet& b, double tol_m) {
  ASSERT_EQ(a.intervals.size(), b.intervals.size());
  ASSERT_GT(a.intervals.size(), 5u);
  for (std::size_t i = 0; i < a.intervals.size(); ++i) {
    const auto& x = a.intervals[i];
    const auto& y = b.intervals[i];
    // Stamps: first beam = last beam - 99.9 ms, one rounding of a ~2 s value.
    EXPECT_NEAR(x.t_start_s, y.t_start_s, 1e-12) << i;
    EXPECT_NEAR(x.t_end_s, y.t_end_s, 1e-12) << i;
    const SE2 d = x.T_lidarStart_lidarEnd.inverse() * y.T_lidarStart_lidarEnd;
    EXPECT_NEAR(std::hypot(d.x, d.y), 0.0, tol_m) << i;
    EXPECT_NEAR(d.yaw, 0.0, tol_m) << i;
  }
}

// 3 s of the arc in the room, kinematic: walls and corners that ICP can lock onto.
Dataset arc() {
  sim::SimConfig config;
  config.scenario = "worlds/scenarios/arc.yaml";
  config.mode = sim::SimMode::kinematic;
  config.duration_s = 3.0;
  return sim::simulate(config).dataset;
}

TEST(CalibrationMotion, LastBeamStampsGiveTheSameIntervals) {
  const Dataset first = arc();
  const Dataset last = stampedAtLastBeam(first);
  for (const bool from_icp : {false, true}) {
    CalibrationMotionOptions options;
    options.from_icp = from_icp;
    const algo::IntervalSet reference = calibrationMotion(first, options).intervals;
    options.stamp_is_last_beam = true;
    // Ground truth: the interpolated pose at the same instant (1e-12 m). ICP: the same points
    // up to the rounding of the beam times, which moves a converged match by far less than 1 um.
    expectSameIntervals(reference, calibrationMotion(last, options).intervals,
                        from_icp ? 1e-6 : 1e-12);
  }
  // Without the flag the stamps are read as first beams: the intervals move by a scan's sweep.
  CalibrationMotionOptions truth;
  truth.from_icp = false;
  const auto a = calibrationMotion(first, truth).intervals.intervals;
  const auto b = calibrationMotion(last, truth).intervals.intervals;
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(b.empty());
  EXPECT_GT(b.front().t_start_s - a.front().t_start_s, 0.03);
}

}  // namespace
}  // namespace slamprep::eval
