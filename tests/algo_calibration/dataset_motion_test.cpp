// Chaining scan-to-scan matches into lidar trajectories: a failed match ends a chain. UMBmark
// runs from a dataset carry the encoder steps their odometry was integrated from.
#include "slamprep/algo/calibration/dataset_motion.hpp"

#include <gtest/gtest.h>

#include "slamprep/core/odometry.hpp"

namespace slamprep::algo {
namespace {

ScanMatch step(std::size_t ref, bool converged) {
  ScanMatch m;
  m.ref = ref;
  m.stamp_ref_s = 0.1 * static_cast<double>(ref);
  m.stamp_cur_s = m.stamp_ref_s + 0.1;
  m.match.converged = converged;
  m.match.T_ref_cur = SE2(0.1, 0.0, 0.05);
  return m;
}

TEST(ChainMatches, FailedMatchesBreakChains) {
  // Scans 0..6; the matches 2->3 and 5->6 fail.
  const std::vector<ScanMatch> matches = {step(0, true), step(1, true), step(2, false),
                                          step(3, true), step(4, true), step(5, false)};
  const MatchChains c = chainMatches(matches);
  EXPECT_EQ(c.failed_matches, 2);
  ASSERT_EQ(c.chains.size(), 2u);
  ASSERT_EQ(c.chains[0].size(), 3u);  // scans 0, 1, 2
  EXPECT_EQ(c.chains[0].frontStamp(), 0.0);
  EXPECT_EQ(c.chains[0][0].value.x, 0.0);  // each chain starts at identity
  const SE2 two = SE2(0.1, 0.0, 0.05) * SE2(0.1, 0.0, 0.05);
  EXPECT_EQ(c.chains[0][2].value.x, two.x);
  EXPECT_EQ(c.chains[0][2].value.yaw, two.yaw);
  ASSERT_EQ(c.chains[1].size(), 3u);  // scans 3, 4, 5; scan 6 alone is no chain
  EXPECT_DOUBLE_EQ(c.chains[1].frontStamp(), 0.3);
  EXPECT_EQ(c.chains[1][0].value.yaw, 0.0);
  EXPECT_TRUE(chainMatches({}).chains.empty());
  EXPECT_TRUE(chainMatches({step(0, false)}).chains.empty());
}

TEST(UmbmarkRunFromDataset, KeepsTheEncoderStepsOfItsOdometry) {
  // 3 s at 100 Hz, the wheels at different, changing rates; truth with the true geometry.
  Dataset d;
  d.info.nominal_geometry = {0.102, 0.0985, 0.52};
  d.info.true_geometry = DiffDriveParams{0.1, 0.1, 0.5};
  for (int k = 0; k <= 300; ++k) {
    const double t = 0.01 * k;
    d.encoders.push_back({t, static_cast<std::int64_t>(std::llround(2000.0 * t)),
                          static_cast<std::int64_t>(std::llround(1500.0 * t + 300.0 * t * t))});
  }
  const int tpr = d.info.ticks_per_revolution;
  d.odom_nominal = integrateEncoders(d.encoders, d.info.nominal_geometry, tpr);
  d.groundtruth = integrateEncoders(d.encoders, *d.info.true_geometry, tpr);
  const std::optional<UmbmarkRun> run = umbmarkRunFromDataset(d);
  ASSERT_TRUE(run);
  ASSERT_EQ(run->steps.size(), 300u);
  const DiffDriveParams& n = d.info.nominal_geometry;
  const SE2 again = integrateSteps(run->steps, n.radius_left_m, n.radius_right_m, n.wheel_base_m);
  const SE2 recorded = between(run->T_world_start_odom, run->T_world_end_odom);
  EXPECT_NEAR(again.x, recorded.x, 1e-12);
  EXPECT_NEAR(again.y, recorded.y, 1e-12);
  EXPECT_NEAR(again.yaw, recorded.yaw, 1e-12);
  EXPECT_FALSE(run->clockwise);  // the right wheel turns faster: counter-clockwise
}

}  // namespace
}  // namespace slamprep::algo
