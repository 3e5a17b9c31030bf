// The local submap (algo/matching/local_submap.hpp): points land in the world frame and come back
// in any frame, the spacing rule (checked against brute force), and forgetting by distance and by
// travel.
#include "slamprep/algo/matching/local_submap.hpp"

#include <gtest/gtest.h>

#include <random>

namespace slamprep::algo {
namespace {

TEST(LocalSubmap, InsertsInTheWorldFrameAndReturnsPointsInAnyFrame) {
  LocalSubmap map;
  const Points2 scan{{1.0, 0.0}, {0.0, 2.0}, {-3.0, 0.5}};
  const SE2 T_world_sensor(1.0, 2.0, 0.3), T_world_ref(-0.5, 0.2, -1.1);
  ASSERT_EQ(map.insert(scan, T_world_sensor, 0.0), 3u);
  const Points2 in_ref = map.pointsIn(T_world_ref);
  ASSERT_EQ(in_ref.size(), 3u);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    EXPECT_LT((map.points()[i].p_world - T_world_sensor * scan[i]).norm(), 1e-12);
    EXPECT_LT((T_world_ref * in_ref[i] - T_world_sensor * scan[i]).norm(), 1e-12);  // inverse
  }
}

TEST(LocalSubmap, APointEntersOnlyWhereTheMapHasNoneWithinTheSpacing) {
  LocalSubmapParams params;
  params.voxel_size_m = 0.1;
  LocalSubmap map(params);
  map.insert({{0.0, 0.0}}, SE2(), 0.0);
  // 0.09 m away (also across a voxel border): refused; 0.11 m away: added.
  EXPECT_EQ(map.insert({{0.09, 0.0}, {-0.05, -0.05}}, SE2(), 0.0), 0u);
  EXPECT_EQ(map.insert({{0.11, 0.0}}, SE2(), 0.0), 1u);
  EXPECT_EQ(map.size(), 2u);
}

// 2000 random points in a 3 m square: no two map points closer than the spacing, and every
// input point has a map point within it (brute force over all pairs).
TEST(LocalSubmap, SpacingMatchesBruteForce) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  Points2 cloud(2000);
  for (auto& p : cloud) p = {u(rng), u(rng)};
  LocalSubmapParams params;
  params.voxel_size_m = 0.1;
  LocalSubmap map(params);
  map.insert(cloud, SE2(0.3, -0.2, 0.7), 0.0);
  const auto& kept = map.points();
  ASSERT_GT(kept.size(), 100u);
  ASSERT_LT(kept.size(), cloud.size());
  for (std::size_t i = 0; i < kept.size(); ++i)
    for (std::size_t j = i + 1; j < kept.size(); ++j)
      ASSERT_GE((kept[i].p_world - kept[j].p_world).norm(), 0.1) << i << " " << j;
  for (const auto& p : cloud) {
    const Eigen::Vector2d p_world = SE2(0.3, -0.2, 0.7) * p;
    double nearest = 1e9;
    for (const auto& s : kept) nearest = std::min(nearest, (s.p_world - p_world).norm());
    EXPECT_LT(nearest, 0.1);
  }
}

TEST(LocalSubmap, PruneDropsPointsFarFromTheRobotOrInsertedLongAgo) {
  LocalSubmapParams params;
  params.max_distance_m = 10.0;
  params.max_travel_m = 20.0;
  LocalSubmap map(params);
  map.insert({{1.0, 0.0}, {9.0, 0.0}}, SE2(), 0.0);  // near and far from (5, 0) at travel 0
  map.insert({{2.0, 1.0}}, SE2(), 15.0);
  EXPECT_EQ(map.prune({-2.0, 0.0}, 15.0), 1u);  // (9, 0) is 11 m away
  EXPECT_EQ(map.size(), 2u);
  EXPECT_EQ(map.prune({-2.0, 0.0}, 21.0), 1u);  // (1, 0) was inserted 21 m of travel ago
  ASSERT_EQ(map.size(), 1u);
  EXPECT_LT((map.points()[0].p_world - Eigen::Vector2d(2.0, 1.0)).norm(), 1e-12);
  // The voxels were rebuilt: a point next to the survivor is refused, one where (1, 0) was isn't.
  EXPECT_EQ(map.insert({{2.01, 1.0}}, SE2(), 21.0), 0u);
  EXPECT_EQ(map.insert({{1.0, 0.0}}, SE2(), 21.0), 1u);
}

}  // namespace
}  // namespace slamprep::algo
