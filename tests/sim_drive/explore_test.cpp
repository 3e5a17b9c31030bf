// The `explore` segment: 240 s of random driving in the L-shaped hall, planned in the world's
// free space, must pass the path check for every seed, cover both wings, and turn both ways
// within the limits. Kinematic mode and a 90-beam lidar keep it fast.

#include "slamprep/sim/drive/explore.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <set>

#include "slamprep/core/error.hpp"
#include "slamprep/sim/drive/simulator.hpp"

namespace slamprep::sim {
namespace {

const std::filesystem::path kRoot(SLAMPREP_SOURCE_DIR);

Scenario exploreScenario(int seed, double duration_s = 240.0) {
  return parseScenario("segments:\n  - {type: explore, duration_s: " + std::to_string(duration_s) +
                           ", seed: " + std::to_string(seed) + "}\n",
                       "explore_test.yaml");
}

SimConfig kinematic() {
  SimConfig c;
  c.mode = SimMode::kinematic;
  c.lidar.beams_per_revolution = 90;
  return c;
}

/// Which 1 m x 1 m cells of the hall the true path passed through.
std::set<std::pair<int, int>> visitedCells(const PoseSeries& truth) {
  std::set<std::pair<int, int>> cells;
  for (const auto& s : truth.samples())
    cells.insert(
        {static_cast<int>(std::floor(s.value.x)), static_cast<int>(std::floor(s.value.y))});
  return cells;
}

TEST(Explore, StaysInTheLShapedHallFor240sWithEverySeed) {
  const World hall = loadWorld(kRoot / "worlds" / "l_hall.yaml");
  const SimConfig c = kinematic();
  for (int seed = 1; seed <= 5; ++seed) {
    SCOPED_TRACE(seed);
    SimResult result;
    // simulate() plans the segment and runs checkPathInWorld on the planned drive.
    ASSERT_NO_THROW(result = simulate(c, hall, exploreScenario(seed)));
    const SimSummary& s = result.summary;
    EXPECT_DOUBLE_EQ(s.duration_s, 240.0);
    // Seeds 1-12 measured: 63-85 m, 46-65 cells, 29-43 rad. Cruise 0.2-0.5 m/s with turns on
    // the spot now and then: over 50 m in 240 s.
    EXPECT_GT(s.distance_m, 50.0);
    EXPECT_LT(s.distance_m, 0.5 * 240.0);
    // The hall has 256 cells of 1 m^2; a 1 m wide track of ~75 m can touch ~75. Over 40 distinct
    // cells (the path does not keep to one loop), and both wings (x > 9 m, y > 9 m) reached.
    const std::set<std::pair<int, int>> cells = visitedCells(result.dataset.groundtruth);
    EXPECT_GT(cells.size(), 40u);
    bool east = false, north = false;
    for (const auto& [x, y] : cells) east |= x >= 9, north |= y >= 9;
    EXPECT_TRUE(east);
    EXPECT_TRUE(north);
    // Turns: at least four full turns' worth of |yaw| (both ways: CommandsRespectTheLimits...).
    EXPECT_GT(s.rotation_rad, 4 * 2 * std::numbers::pi);
  }
}

TEST(Explore, StartsAnywhereInTheHall) {
  // Start poses across both wings, near walls and pillars, facing every way: the plan begins
  // where the robot is and passes the path check (kinematic replay, 240 s) from each.
  World hall = loadWorld(kRoot / "worlds" / "l_hall.yaml");
  const Scene scene(hall);
  const SimConfig c = kinematic();
  int k = 0;
  for (const Eigen::Vector3d& start :
       {Eigen::Vector3d(1.0, 1.0, 0.0), Eigen::Vector3d(19.0, 7.0, 3.0),
        Eigen::Vector3d(10.0, 4.0, 1.5), Eigen::Vector3d(6.7, 5.0, -2.0),
        Eigen::Vector3d(4.0, 19.0, -1.0), Eigen::Vector3d(7.0, 10.0, 2.5),
        Eigen::Vector3d(1.0, 13.0, -0.5), Eigen::Vector3d(16.0, 1.0, 0.7)}) {
    SCOPED_TRACE(start.transpose());
    const SE2 T_world_start(start.x(), start.y(), start.z());
    const Scenario planned = planExplore(scene, exploreScenario(++k), c, T_world_start);
    EXPECT_NO_THROW(checkPathInWorld(scene, planned, c, T_world_start, 240.0));
  }
}

TEST(Explore, CommandsRespectTheLimitsAndTurnBothWays) {
  const World hall = loadWorld(kRoot / "worlds" / "l_hall.yaml");
  const Scene scene(hall);
  const SimConfig c = kinematic();
  const Scenario planned = planExplore(scene, exploreScenario(3), c, hall.T_world_start);
  ASSERT_EQ(planned.profile.segments().size(), 1u);
  const ProfileSegment& seg = planned.profile.segments()[0];
  EXPECT_EQ(seg.explore, nullptr);
  EXPECT_DOUBLE_EQ(seg.end_s(), 240.0);
  EXPECT_EQ(seg.knots.front().value, Eigen::Vector2d::Zero());
  EXPECT_EQ(seg.knots.back().value, Eigen::Vector2d::Zero());
  double left_s = 0.0, right_s = 0.0;
  const AccelerationLimits limits;  // the scenario's (defaults)
  for (std::size_t k = 1; k < seg.knots.size(); ++k) {
    const double dt = seg.knots[k].t_s - seg.knots[k - 1].t_s;
    const Eigen::Vector2d dc = seg.knots[k].value - seg.knots[k - 1].value;
    ASSERT_GT(dt, 0.0);
    EXPECT_LE(std::abs(dc.x()) / dt, limits.linear_mps2 * (1 + 1e-9));
    EXPECT_LE(std::abs(dc.y()) / dt, limits.angular_radps2 * (1 + 1e-9));
    const Eigen::Vector2d& v = seg.knots[k].value;
    EXPECT_LE(v.x(), 0.5 + 1e-12);
    EXPECT_GE(v.x(), 0.0);
    EXPECT_LE(std::abs(v.y()), 1.0 + 1e-12);
    if (v.y() > 0.1) left_s += dt;
    if (v.y() < -0.1) right_s += dt;
  }
  // Both turn directions take a real share of the drive (at least 10 % of it each).
  EXPECT_GT(left_s, 24.0);
  EXPECT_GT(right_s, 24.0);
}

TEST(Explore, SameSeedSameKnotsOtherSeedOtherPath) {
  const World hall = loadWorld(kRoot / "worlds" / "l_hall.yaml");
  const Scene scene(hall);
  const SimConfig c = kinematic();
  const auto knots = [&](int seed) {
    return planExplore(scene, exploreScenario(seed, 60.0), c, hall.T_world_start)
        .profile.segments()[0]
        .knots;
  };
  const auto a = knots(11), b = knots(11), other = knots(12);
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].t_s, b[k].t_s);
    EXPECT_EQ(a[k].value, b[k].value);  // bit for bit
  }
  // And the simulated data: the same truth, pose for pose, bit for bit.
  const SimResult run1 = simulate(c, hall, exploreScenario(11, 60.0));
  const SimResult run2 = simulate(c, hall, exploreScenario(11, 60.0));
  ASSERT_EQ(run1.dataset.groundtruth.size(), run2.dataset.groundtruth.size());
  for (std::size_t k = 0; k < run1.dataset.groundtruth.size(); ++k) {
    const SE2& p1 = run1.dataset.groundtruth[k].value;
    const SE2& p2 = run2.dataset.groundtruth[k].value;
    ASSERT_TRUE(p1.x == p2.x && p1.y == p2.y && p1.yaw == p2.yaw) << k;
  }
  bool differs = a.size() != other.size();
  for (std::size_t k = 0; !differs && k < a.size(); ++k) differs = a[k].value != other[k].value;
  EXPECT_TRUE(differs);
}

TEST(Explore, FollowsOtherSegmentsFromWhereTheyEnd) {
  // A straight and a spin first: the explore plan starts from the pose they reach.
  const World hall = loadWorld(kRoot / "worlds" / "l_hall.yaml");
  const Scenario s = parseScenario(
      "segments:\n  - {type: straight, distance_m: 2.0}\n  - {type: spin, angle_deg: 90}\n"
      "  - {type: explore, duration_s: 120, seed: 4}\n  - {type: spin, angle_deg: -90}\n",
      "explore_test.yaml");
  SimResult result;
  ASSERT_NO_THROW(result = simulate(kinematic(), hall, s));
  EXPECT_NEAR(result.summary.duration_s, s.profile.duration_s(), 1e-3);  // 1 kHz steps
  EXPECT_GT(result.summary.distance_m, 20.0);
}

TEST(Explore, RefusesAWorldTooLargeForItsGrid) {
  World huge;
  huge.source = "huge(test)";
  huge.walls.push_back({{-1000.0, -1000.0}, {1000.0, 1000.0}, 0.2, 2.0});
  huge.T_world_start = SE2(5.0, 0.0, 0.0);
  try {
    simulate(kinematic(), huge, exploreScenario(1, 10.0));
    FAIL() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("grid_resolution_m"), std::string::npos) << e.what();
  }
}

TEST(Explore, RefusesBadKeys) {
  EXPECT_THROW(parseScenario("segments:\n  - {type: explore}\n", "t.yaml"), InputError);
  EXPECT_THROW(parseScenario("segments:\n  - {type: explore, duration_s: 10, max_speed_mps: 0.1, "
                             "min_speed_mps: 0.3}\n",
                             "t.yaml"),
               InputError);
  EXPECT_THROW(
      parseScenario("segments:\n  - {type: explore, duration_s: 10, clearnce_m: 1}\n", "t.yaml"),
      InputError);
}

}  // namespace
}  // namespace slamprep::sim
