// Returns no other moment supports: the grid search against brute force, few in a still room
// seen from its true poses, many once people walk about the robot.
#include "slamprep/eval/bench/transient_returns.hpp"

#include <gtest/gtest.h>

#include <filesystem>

#include "slamprep/sim/drive/scenario.hpp"
#include "slamprep/sim/drive/simulator.hpp"
#include "slamprep/sim/physics/world.hpp"

namespace slamprep::eval {
namespace {

/// A figure eight in box_room.yaml, 10 mm range noise, with `people` about the robot.
Dataset figureEight(int people) {
  sim::SimConfig c;
  c.lidar.beams_per_revolution = 360;
  c.people.count = people;
  c.people.distance_m = 1.0;  // within the 6 x 4 m room
  const sim::World world =
      sim::loadWorld(std::filesystem::path(SLAMPREP_SOURCE_DIR) / "worlds" / "box_room.yaml");
  const sim::Scenario s = sim::parseScenario(
      "segments:\n  - {type: figure_eight, radius_m: 0.8, speed_mps: 0.4}\n", "t.yaml");
  return sim::simulate(c, world, s).dataset;
}

/// Every `every`-th scan.
std::vector<char> everyNth(const Dataset& d, std::size_t every) {
  std::vector<char> use(d.scans.size());
  for (std::size_t k = 0; k < use.size(); k += every) use[k] = 1;
  return use;
}

/// The definition, directly: every pair of placed returns.
std::size_t bruteForce(const Dataset& d, const std::vector<char>& use, const TransientParams& p) {
  struct R {
    Eigen::Vector2d p;
    double t;
  };
  std::vector<R> returns;
  for (std::size_t k = 0; k < d.scans.size(); ++k) {
    if (!use[k]) continue;
    const LaserScan& s = d.scans[k].scan;
    for (std::size_t i = 0; i < s.size(); ++i) {
      if (!s.valid(i) || s.ranges_m[i] < p.min_range_m || s.ranges_m[i] > 30.0) continue;
      const auto T = d.groundtruth.at(s.beamTime(i));
      if (!T) continue;
      returns.push_back({*T * (d.info.T_base_lidar * s.point(i)), s.beamTime(i)});
    }
  }
  std::size_t transient = 0;
  for (const R& a : returns) {
    bool supported = false;
    for (const R& b : returns)
      if (std::abs(b.t - a.t) >= p.min_gap_s && (b.p - a.p).norm() <= p.radius_m) {
        supported = true;
        break;
      }
    if (!supported) ++transient;
  }
  return transient;
}

TEST(TransientReturns, TheGridFindsWhatBruteForceFinds) {
  const Dataset d = figureEight(2);
  const std::vector<char> use = everyNth(d, 15);
  TransientParams p;
  p.radius_m = 0.03;
  const TransientReturns r = transientReturns(d, d.groundtruth, use, 30.0, p);
  EXPECT_GT(r.returns, 2000u);
  EXPECT_GT(r.transient, 20u);  // the people's, so the comparison is not of zeros
  EXPECT_EQ(r.transient, bruteForce(d, use, p));
}

// A still room seen from the true poses: only the noise's few strays; people walking about the
// robot: a share of every scan.
TEST(TransientReturns, AStillRoomHasFewPeopleMany) {
  const Dataset still = figureEight(0), walked = figureEight(3);
  const double f_still =
      transientReturns(still, still.groundtruth, everyNth(still, 1), 30.0).fraction();
  const double f_walked =
      transientReturns(walked, walked.groundtruth, everyNth(walked, 1), 30.0).fraction();
  EXPECT_LT(f_still, 0.005);
  EXPECT_GT(f_walked, 0.02);  // 0.036 at seed 1: people come back near where they were
}

}  // namespace
}  // namespace slamprep::eval
