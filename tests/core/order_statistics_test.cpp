// core/order_statistics: the O(n) quantile against the definition on a sorted copy, the
// type-7 endpoints, and the median of even and odd samples.
#include "slamprep/core/order_statistics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

namespace slamprep {
namespace {

// Hyndman and Fan's type 7 written out on a fully sorted copy: the brute-force reference.
double type7(std::vector<double> x, double q) {
  std::sort(x.begin(), x.end());
  const double h = static_cast<double>(x.size() - 1) * q;
  const double lo = x[static_cast<std::size_t>(std::floor(h))];
  const double hi = x[static_cast<std::size_t>(std::ceil(h))];
  return lo + (h - std::floor(h)) * (hi - lo);
}

TEST(OrderStatistics, QuantileEndpointsAndInterpolation) {
  const std::vector<double> x = {0.0, 10.0, 20.0};
  EXPECT_EQ(quantileOfSorted(x, 0.0), 0.0);
  EXPECT_EQ(quantileOfSorted(x, 1.0), 20.0);
  EXPECT_DOUBLE_EQ(quantileOfSorted(x, 0.25), 5.0);
  EXPECT_DOUBLE_EQ(quantile({20.0, 0.0, 10.0}, 0.75), 15.0);
  EXPECT_EQ(quantile({}, 0.5), 0.0);
  EXPECT_EQ(quantile({7.0}, 0.99), 7.0);
}

TEST(OrderStatistics, MedianOfAnEvenSampleIsTheMeanOfItsMiddleValues) {
  EXPECT_EQ(median({3.0, 1.0, 2.0}), 2.0);
  EXPECT_EQ(median({4.0, 1.0, 3.0, 2.0}), 2.5);
  EXPECT_EQ(median({5.0, 5.0, 1.0, 9.0}), 5.0);
}

TEST(OrderStatistics, QuantileInLinearTimeEqualsTheSortedDefinition) {
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (std::size_t n : {1u, 2u, 3u, 10u, 101u, 1000u}) {
    std::vector<double> x(n);
    for (double& v : x) v = std::round(noise(rng) * 4.0) / 4.0;  // ties included
    for (double q : {0.0, 0.01, 0.25, 0.5, 0.9, 0.95, 0.999, 1.0})
      EXPECT_DOUBLE_EQ(quantile(x, q), type7(x, q)) << "n " << n << " q " << q;
  }
}

TEST(OrderStatistics, MedianSpacingIsTheMedianStep) {
  EXPECT_EQ(medianSpacing({}), 0.0);
  EXPECT_EQ(medianSpacing({1.0}), 0.0);
  EXPECT_DOUBLE_EQ(medianSpacing({0.0, 0.1, 0.2, 0.5, 0.6}), 0.1);  // one late stamp
  EXPECT_DOUBLE_EQ(medianSpacing({0.0, 0.1, 0.3}), 0.15);
}

}  // namespace
}  // namespace slamprep
