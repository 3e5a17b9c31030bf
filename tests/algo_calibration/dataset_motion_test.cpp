// Chaining scan-to-scan matches into lidar trajectories: a failed match ends a chain.
#include "algo/calibration/dataset_motion.hpp"

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace slamprep::algo
