#include "slamprep/core/time_series.hpp"

#include <gtest/gtest.h>

namespace slamprep {
namespace {

TEST(TimeSeries, BracketsAndInterpolatesLinearly) {
  TimeSeries<double> s;
  s.push_back(0.0, 10.0);
  s.push_back(1.0, 20.0);
  s.push_back(3.0, 0.0);
  const auto b = s.bracket(2.0);
  ASSERT_TRUE(b.has_value());
  EXPECT_EQ(b->index, 1u);
  EXPECT_DOUBLE_EQ(b->fraction, 0.5);
  EXPECT_DOUBLE_EQ(*s.at(0.25), 12.5);
  EXPECT_DOUBLE_EQ(*s.at(2.0), 10.0);
  EXPECT_DOUBLE_EQ(*s.at(3.0), 0.0);  // the last stamp is inside
  EXPECT_DOUBLE_EQ(*s.at(1.0), 20.0);
}

TEST(TimeSeries, RefusesToExtrapolate) {
  TimeSeries<double> s;
  EXPECT_FALSE(s.at(0.0).has_value());
  s.push_back(1.0, 1.0);
  s.push_back(2.0, 2.0);
  EXPECT_FALSE(s.at(0.999).has_value());
  EXPECT_FALSE(s.at(2.001).has_value());
  EXPECT_TRUE(s.covers(1.5));
}

TEST(TimeSeries, PosesInterpolateGeodesically) {
  PoseSeries s;
  s.push_back(0.0, SE2());
  s.push_back(2.0, SE2::exp({2.0, 0.0, 2.0}));
  const SE2 mid = *s.at(1.0);
  const SE2 expected = SE2::exp({1.0, 0.0, 1.0});
  EXPECT_NEAR(mid.x, expected.x, 1e-12);
  EXPECT_NEAR(mid.y, expected.y, 1e-12);
  EXPECT_NEAR(mid.yaw, expected.yaw, 1e-12);
}

}  // namespace
}  // namespace slamprep
