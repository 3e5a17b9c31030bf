// The no-return value rule (eval/formats/range_limit.hpp): a spike at the largest reading is the
// sensor's "no return"; a far wall spread over neighbouring bins, or a handful of readings, is not.
#include "slamprep/eval/formats/range_limit.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace slamprep::eval {
namespace {

/// One scan holding `ranges`, range_max 80 m (CARMEN's convention).
LaserScan scanOf(const std::vector<double>& ranges) {
  LaserScan s;
  s.ranges_m = ranges;
  s.angle_increment_rad = 0.01;
  s.range_min_m = 0.0;
  s.range_max_m = 80.0;
  return s;
}

/// `n` readings spread evenly over [from, to).
std::vector<double> spread(std::size_t n, double from, double to) {
  std::vector<double> r;
  for (std::size_t i = 0; i < n; ++i) r.push_back(from + (to - from) * double(i) / double(n));
  return r;
}

TEST(NoReturnValue, ASpikeAtTheLargestReadingIsFound) {
  RangeHistogram h;
  std::vector<double> r = spread(10000, 0.5, 45.0);
  r.insert(r.end(), 80, 50.0);  // 0.79 % at 50.00 m, nothing in the metre below
  h.add(scanOf(r));
  const auto v = noReturnValue(h);
  ASSERT_TRUE(v);
  EXPECT_EQ(v->value_m, 50.0);
  EXPECT_EQ(v->readings, 80u);
  EXPECT_EQ(v->times_below, 0.0);  // the metre below is empty
}

TEST(NoReturnValue, AFarWallSpreadOverBinsIsAReturn) {
  RangeHistogram h;
  std::vector<double> r = spread(10000, 0.5, 9.0);
  const std::vector<double> wall = spread(2000, 9.0, 9.5);  // 40 per 1 cm bin up to the largest
  r.insert(r.end(), wall.begin(), wall.end());
  h.add(scanOf(r));
  EXPECT_FALSE(noReturnValue(h));
  EXPECT_FALSE(rangeReport(h, std::nullopt, 0).no_return);
}

TEST(NoReturnValue, AHandfulAtTheLargestReadingIsNotEnough) {
  RangeHistogram h;
  std::vector<double> r = spread(100000, 0.5, 20.0);
  r.insert(r.end(), 9, 30.0);  // under both the 10 readings and the 0.1 % floor
  h.add(scanOf(r));
  EXPECT_FALSE(noReturnValue(h));
}

TEST(NoReturnValue, AppliedTheReadingsBecomeNoReturnAndRangeMaxTheValue) {
  LaserScan s = scanOf({3.0, 49.995, 50.0, 12.0});
  EXPECT_EQ(applyNoReturnValue(s, 50.0), 2u);
  EXPECT_EQ(s.range_max_m, 50.0);
  EXPECT_TRUE(std::isinf(s.ranges_m[1]) && std::isinf(s.ranges_m[2]));
  EXPECT_EQ(s.ranges_m[0], 3.0);
  EXPECT_EQ(s.ranges_m[3], 12.0);
}

TEST(NoReturnValue, AMaxRangeBelowTheValueLeavesItToTheCut) {
  RangeHistogram h;
  std::vector<double> r = spread(10000, 0.5, 45.0);
  r.insert(r.end(), 80, 50.0);
  h.add(scanOf(r));
  EXPECT_FALSE(rangeReport(h, 40.0, 0).no_return);  // --max-range 40 cuts them already
  const RangeReport kept = rangeReport(h, std::nullopt, 0);
  ASSERT_TRUE(kept.no_return);
  EXPECT_FALSE(kept.no_return_applied);
  EXPECT_NE(kept.text().find("give --max-range 49.98"), std::string::npos) << kept.text();
}

}  // namespace
}  // namespace slamprep::eval
