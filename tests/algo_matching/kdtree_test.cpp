#include "slamprep/algo/matching/kdtree.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>

namespace slamprep::algo {
namespace {

Points2 randomPoints(std::mt19937& rng, std::size_t n, double half_extent_m) {
  std::uniform_real_distribution<double> u(-half_extent_m, half_extent_m);
  Points2 points(n);
  for (auto& p : points) p = {u(rng), u(rng)};
  return points;
}

std::vector<double> bruteForceDistancesSq(const Points2& points, const Eigen::Vector2d& q) {
  std::vector<double> d;
  for (const auto& p : points) d.push_back((p - q).squaredNorm());
  std::sort(d.begin(), d.end());
  return d;
}

TEST(KdTree2, NearestEqualsBruteForce) {
  std::mt19937 rng(7);
  const Points2 points = randomPoints(rng, 2000, 10.0);
  const KdTree2 tree(points);
  for (const auto& q : randomPoints(rng, 500, 12.0)) {
    const auto nn = tree.nearest(q);
    ASSERT_TRUE(nn);
    const auto brute = bruteForceDistancesSq(points, q);
    // Both are the same floating-point expression on the same pair: exactly equal.
    EXPECT_EQ(nn->distance_sq_m2, brute.front());
    EXPECT_EQ((points[nn->index] - q).squaredNorm(), brute.front());
  }
}

TEST(KdTree2, KNearestEqualsBruteForce) {
  std::mt19937 rng(11);
  const Points2 points = randomPoints(rng, 700, 5.0);
  const KdTree2 tree(points);
  for (const auto& q : randomPoints(rng, 200, 6.0)) {
    const auto knn = tree.nearestK(q, 7);
    const auto brute = bruteForceDistancesSq(points, q);
    ASSERT_EQ(knn.size(), 7u);
    for (std::size_t k = 0; k < knn.size(); ++k) EXPECT_EQ(knn[k].distance_sq_m2, brute[k]);
  }
}

// The hinted search and the allocation-free k-nearest answer exactly as brute force, whatever
// the hint (a random point, usually a bad one).
TEST(KdTree2, HintedAndInPlaceSearchesEqualBruteForce) {
  std::mt19937 rng(13);
  const Points2 points = randomPoints(rng, 720, 6.0);
  const KdTree2 tree(points);
  std::uniform_int_distribution<std::size_t> any(0, points.size() - 1);
  for (const auto& q : randomPoints(rng, 300, 7.0)) {
    const auto brute = bruteForceDistancesSq(points, q);
    EXPECT_EQ(tree.nearest(q, any(rng))->distance_sq_m2, brute.front());
    Neighbor two[2];
    ASSERT_EQ(tree.nearestInto(q, 2, two), 2u);
    EXPECT_EQ(two[0].distance_sq_m2, brute[0]);
    EXPECT_EQ(two[1].distance_sq_m2, brute[1]);
  }
}

TEST(KdTree2, EmptyAndSmallTrees) {
  const KdTree2 empty(Points2{});
  EXPECT_FALSE(empty.nearest({0.0, 0.0}));
  EXPECT_TRUE(empty.nearestK({0.0, 0.0}, 3).empty());
  const KdTree2 two(Points2{{0.0, 0.0}, {1.0, 0.0}});
  EXPECT_EQ(two.nearestK({0.9, 0.0}, 5).size(), 2u);
  EXPECT_EQ(two.nearest({0.9, 0.0})->index, 1u);
}

}  // namespace
}  // namespace slamprep::algo
