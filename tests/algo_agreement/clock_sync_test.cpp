// The clock sync (algo/agreement/dataset_sources.hpp) on a synthetic drive whose clocks agree:
// a first measure that the second takes back moves nothing and leaves the streams as logged.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "slamprep/algo/agreement/dataset_sources.hpp"
#include "slamprep/core/odometry.hpp"

namespace slamprep::algo {
namespace {

/// 60 s at 50 Hz of a robot weaving at 0.2 m/s: encoders of `g` (2^20 ticks) and the true
/// poses, on one clock.
struct Weave {
  Dataset dataset;
  PoseSeries truth;
};

Weave weave(const DiffDriveParams& g) {
  Weave d;
  d.dataset.info.nominal_geometry = g;
  d.dataset.info.ticks_per_revolution = 1 << 20;
  const double rad_per_tick = radiansPerTick(d.dataset.info.ticks_per_revolution);
  Eigen::Vector2d phi = Eigen::Vector2d::Zero();
  double yaw = 0.0;
  const double dt = 0.02;
  for (int k = 0; k * dt <= 60.0; ++k) {
    const double t = k * dt;
    d.dataset.encoders.push_back(
        {t, std::llround(phi.x() / rad_per_tick), std::llround(phi.y() / rad_per_tick)});
    d.truth.push_back(t, SE2(0.0, 0.0, yaw));
    const double w = 0.8 * std::sin(0.7 * t) + 0.3 * std::sin(2.3 * t);
    phi += g.wheelRates(0.2, w) * dt;
    yaw += w * dt;
  }
  return d;
}

/// A first agreement that says the scans lag the wheels by `lag_s`.
SensorAgreement firstMeasure(double lag_s) {
  SensorAgreement a;
  PairAgreement p;
  p.a = "wheels";
  p.b = "scans";
  p.lag_s = lag_s;
  p.kept = 50;
  a.pairs.push_back(p);
  return a;
}

TEST(ClockSync, AFirstMeasureTheSecondTakesBackMovesNothing) {
  Weave d = weave({0.033, 0.033, 0.16});
  const std::vector<EncoderSample> logged = d.dataset.encoders;
  int matches = 0;
  const double moved =
      syncOntoScanClock(d.dataset, firstMeasure(0.05), 0.02, 0.005, [&](const Dataset&) {
        ++matches;
        return std::vector<PoseSeries>{d.truth};
      });
  EXPECT_EQ(moved, 0.0);
  EXPECT_EQ(matches, 2);  // after the first shift, and again on the streams as logged
  ASSERT_EQ(d.dataset.encoders.size(), logged.size());
  for (std::size_t k = 0; k < logged.size(); ++k)
    EXPECT_EQ(d.dataset.encoders[k].stamp_s, logged[k].stamp_s);
}

TEST(ClockSync, ARealDelayIsMovedAndMeasuredAgain) {
  Weave d = weave({0.033, 0.033, 0.16});
  PoseSeries late;  // the scans stamped 0.06 s after the wheels
  for (const auto& [t, T] : d.truth.samples()) late.push_back(t + 0.06, T);
  const double moved =
      syncOntoScanClock(d.dataset, firstMeasure(0.05), 0.02, 0.005,
                        [&](const Dataset&) { return std::vector<PoseSeries>{late}; });
  EXPECT_NEAR(moved, 0.06, 0.005);
  EXPECT_NEAR(d.dataset.encoders.front().stamp_s, moved, 1e-12);
}

}  // namespace
}  // namespace slamprep::algo
