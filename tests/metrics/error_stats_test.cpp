#include "slamprep/eval/metrics/error_stats.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace slamprep::eval {
namespace {

TEST(ErrorStats, HandComputedFourValues) {
  // {1, 2, 3, 4} in scrambled order: mean 2.5, rmse sqrt(30/4), population var 1.25,
  // median (2+3)/2, p95: h = 3 * 0.95 = 2.85 -> 3 + 0.85 * (4 - 3) = 3.85.
  const ErrorStats s = summarize({3.0, 1.0, 4.0, 2.0});
  ASSERT_TRUE(s.ok) << s.reason;
  EXPECT_EQ(s.count, 4u);
  EXPECT_DOUBLE_EQ(s.mean, 2.5);
  EXPECT_DOUBLE_EQ(s.rmse, std::sqrt(7.5));
  EXPECT_DOUBLE_EQ(s.std, std::sqrt(1.25));
  EXPECT_DOUBLE_EQ(s.median, 2.5);
  EXPECT_DOUBLE_EQ(s.p95, 3.85);
  EXPECT_EQ(s.min, 1.0);
  EXPECT_EQ(s.max, 4.0);
}

TEST(ErrorStats, OddCountMedianIsTheMiddleValue) {
  const ErrorStats s = summarize({5.0, -1.0, 2.0});
  EXPECT_EQ(s.median, 2.0);
  EXPECT_DOUBLE_EQ(s.p95, 2.0 + 0.9 * 3.0);  // h = 2 * 0.95 = 1.9
}

TEST(ErrorStats, SingleValueHasZeroSpread) {
  const ErrorStats s = summarize({0.25});
  ASSERT_TRUE(s.ok);
  EXPECT_EQ(s.median, 0.25);
  EXPECT_EQ(s.p95, 0.25);
  EXPECT_EQ(s.std, 0.0);
  EXPECT_EQ(s.rmse, 0.25);
}

TEST(ErrorStats, StdIsStableForLargeOffsets) {
  // One-pass sum-of-squares would lose every digit here: mean 1e9, std 1.
  const ErrorStats s = summarize({1e9 - 1, 1e9 + 1});
  EXPECT_DOUBLE_EQ(s.std, 1.0);
}

TEST(ErrorStats, RefusesEmptyAndNonFinite) {
  EXPECT_FALSE(summarize({}).ok);
  EXPECT_EQ(summarize({}).reason, "no values");
  const ErrorStats s = summarize({1.0, std::numeric_limits<double>::quiet_NaN()});
  EXPECT_FALSE(s.ok);
  EXPECT_EQ(s.reason, "value 1 is not finite");
  EXPECT_EQ(s.mean, 0.0);  // never NaN in a report
  EXPECT_FALSE(summarize({std::numeric_limits<double>::infinity()}).ok);
}

}  // namespace
}  // namespace slamprep::eval
