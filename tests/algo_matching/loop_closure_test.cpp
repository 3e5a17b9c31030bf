#include "slamprep/algo/matching/loop_closure.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "slamprep/tests/algo_deskew/synthetic_world.hpp"

namespace slamprep::algo {
namespace {

using slamprep::testing::roomWorld;
using slamprep::testing::standingScan;

// One link and one loop weigh the same, so a loop over n links spreads its correction c as c /
// (n + 1) per link: n d^2 + (n d - c)^2 is least at d = c / (n + 1).
TEST(HeadingCorrections, OneLoopSpreadsEvenlyOverItsLinks) {
  const double c = 0.01;
  const std::vector<double> delta = headingCorrections(11, {{0, 10, c}});
  ASSERT_EQ(delta.size(), 11u);
  for (std::size_t i = 0; i < delta.size(); ++i) EXPECT_NEAR(delta[i], i * c / 11.0, 1e-12) << i;
}

TEST(HeadingCorrections, NoLoopsNoCorrection) {
  for (const double d : headingCorrections(5, {})) EXPECT_EQ(d, 0.0);
}

// A scan from a standing lidar: 720 beams over the full turn, exact ranges.
Points2 fullTurnScan(const SE2& T_world_lidar) {
  return standingScan(roomWorld(), T_world_lidar, 720);
}

// Two laps of a 1 m circle, 100 poses a lap, 0.1 s apart; the chain is the truth with every
// link's heading off by `drift_rad`, as chained scan matches drift.
struct TwoLaps {
  PoseSeries truth, chain;
  std::vector<Points2> scans;
};

TwoLaps twoLaps(double drift_rad) {
  TwoLaps out;
  for (int i = 0; i <= 200; ++i) {
    const double phi = 2.0 * std::numbers::pi * i / 100.0;
    out.truth.push_back(0.1 * i, SE2(std::cos(phi), std::sin(phi), phi + std::numbers::pi / 2));
    out.scans.push_back(fullTurnScan(out.truth[i].value));
  }
  out.chain.push_back(0.0, out.truth[0].value);
  for (std::size_t i = 0; i + 1 < out.truth.size(); ++i) {
    const SE2 link = between(out.truth[i].value, out.truth[i + 1].value);
    out.chain.push_back(out.truth[i + 1].stamp_s,
                        out.chain[i].value * SE2(link.x, link.y, link.yaw + drift_rad));
  }
  return out;
}

std::vector<const Points2*> pointers(const std::vector<Points2>& scans) {
  std::vector<const Points2*> out;
  for (const Points2& s : scans) out.push_back(&s);
  return out;
}

LoopClosureParams lapParams() {
  LoopClosureParams params;
  params.min_gap_s = 5.0;  // a lap takes 10 s
  return params;
}

double headingError(const PoseSeries& chain, const PoseSeries& truth, std::size_t i) {
  return normalizeAngle(chain[i].value.yaw - truth[i].value.yaw);
}

TEST(CloseLoops, RemovesTheHeadingDriftOfAChain) {
  const double drift = 1e-4;  // 0.02 rad over the 200 links
  const TwoLaps laps = twoLaps(drift);
  const LoopCorrection c = closeLoops(laps.chain, pointers(laps.scans), lapParams());
  ASSERT_GE(c.loops.size(), 9u);  // one per keyframe of the second lap
  EXPECT_EQ(c.refused, 0);
  EXPECT_EQ(c.candidates, static_cast<int>(c.loops.size()));
  // The loops measure the drift of a lap exactly; the graph takes it back out of every link of
  // the second lap, which the first lap's loops span (the start pose is held).
  const double before = std::abs(headingError(laps.chain, laps.truth, 200));
  const double after = std::abs(headingError(c.T_world_lidar, laps.truth, 200));
  EXPECT_NEAR(before, 200 * drift, 1e-9);
  EXPECT_LT(after, 0.1 * before);
  // Headings change, translations of every link stay as matched.
  for (std::size_t i = 0; i + 1 < laps.chain.size(); ++i) {
    const SE2 in = between(laps.chain[i].value, laps.chain[i + 1].value);
    const SE2 out = between(c.T_world_lidar[i].value, c.T_world_lidar[i + 1].value);
    EXPECT_NEAR(out.x, in.x, 1e-12);
    EXPECT_NEAR(out.y, in.y, 1e-12);
  }
  EXPECT_GT(c.max_link_change_rad, 0.5 * drift);
  EXPECT_LT(c.max_link_change_rad, 1.5 * drift);
}

TEST(CloseLoops, RefusesDirectMatchesThatDisagreeWithTheChain) {
  const TwoLaps laps = twoLaps(1e-4);
  LoopClosureParams params = lapParams();
  params.max_disagreement_rad = 1e-5;  // below the 0.01 rad a lap drifted
  const LoopCorrection c = closeLoops(laps.chain, pointers(laps.scans), params);
  EXPECT_GT(c.candidates, 0);
  EXPECT_EQ(c.refused, c.candidates);
  EXPECT_TRUE(c.loops.empty());
  for (std::size_t i = 0; i < laps.chain.size(); ++i)
    EXPECT_EQ(c.T_world_lidar[i].value.yaw, laps.chain[i].value.yaw);
}

TEST(CloseLoops, NoLoopsInAChainShorterThanTheGap) {
  const TwoLaps laps = twoLaps(0.0);
  LoopClosureParams params;
  params.min_gap_s = 30.0;  // the chain lasts 20 s
  const LoopCorrection c = closeLoops(laps.chain, pointers(laps.scans), params);
  EXPECT_EQ(c.candidates, 0);
  EXPECT_TRUE(c.loops.empty());
}

}  // namespace
}  // namespace slamprep::algo
