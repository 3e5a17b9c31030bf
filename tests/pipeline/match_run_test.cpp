// The scan-matching error against truth that `slamprep match` prints and the bench records.
#include "slamprep/eval/pipeline/match_run.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace slamprep::eval {
namespace {

TEST(ScanMatchError, ComparesConvergedMatchesWithTheTrueMotion) {
  // True lidar: the same 0.1 m and 0.02 rad step every 0.1 s, four poses.
  const SE2 step(0.1, 0.0, 0.02);
  PoseSeries truth;
  SE2 T_world_lidar;
  for (int k = 0; k < 4; ++k, T_world_lidar = T_world_lidar * step)
    truth.push_back(0.1 * k, T_world_lidar);
  auto match = [](std::size_t ref, double t0, bool converged, const SE2& T) {
    algo::ScanMatch m;
    m.ref = ref;
    m.stamp_ref_s = t0;
    m.stamp_cur_s = t0 + 0.1;
    m.match.converged = converged;
    m.match.T_ref_cur = T;
    return m;
  };
  const SE2 exact = step;
  const SE2 off = exact * SE2(0.003, -0.004, 0.001);  // 5 mm and 1 mrad off
  const std::vector<algo::ScanMatch> matches = {
      match(0, 0.0, true, exact), match(1, 0.1, true, off), match(2, 0.2, false, exact),
      match(3, 0.3, true, exact)};  // the last one ends beyond the truth: not compared
  const ScanMatchError e = scanMatchError(matches, truth);
  EXPECT_EQ(e.pairs, 4u);
  EXPECT_EQ(e.converged, 3u);
  EXPECT_EQ(e.compared, 2u);
  ASSERT_TRUE(e.translation_m.ok);
  // Composition and its inverse round to ~1e-17 m; the 5 mm error comes back to 1e-12.
  EXPECT_NEAR(e.translation_m.max, 0.005, 1e-12);
  EXPECT_NEAR(e.translation_m.mean, 0.0025, 1e-12);
  EXPECT_NEAR(e.rotation_deg.max, 0.001 * 180.0 / std::numbers::pi, 1e-9);
  const ScanMatchError none = scanMatchError(matches, PoseSeries());
  EXPECT_EQ(none.compared, 0u);
  EXPECT_FALSE(none.translation_m.ok);
}

TEST(ScanMatchError, MatchesJsonlHasOneLinePerPair) {
  algo::ScanMatch m;
  m.stamp_ref_s = 1.0;
  m.stamp_cur_s = 1.1;
  m.match.reason = "too few points";
  const std::string text = formatMatches({m, m});
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 2);
  EXPECT_EQ(text.find("{\"stamp_ref\":1.0,\"stamp_cur\":1.1,\"T_ref_cur\":[0.0,0.0,0.0]"), 0u);
  EXPECT_NE(text.find("\"reason\":\"too few points\""), std::string::npos);
}

}  // namespace
}  // namespace slamprep::eval
