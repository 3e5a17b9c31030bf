// The robot profiles a user copies (worlds/robots/*.json): each one loads, says what its file
// says, and drives its calibration scenario in physics mode without tipping or slipping away.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "slamprep/sim/drive/config.hpp"
#include "slamprep/sim/drive/scenario.hpp"
#include "slamprep/sim/drive/simulator.hpp"
#include "slamprep/sim/physics/world.hpp"

namespace slamprep::sim {
namespace {

const std::filesystem::path kWorlds = std::filesystem::path(SLAMPREP_SOURCE_DIR) / "worlds";

SimConfig profile(const std::string& name) {
  std::ifstream in(kWorlds / "robots" / name);
  return configFromJson(nlohmann::json::parse(in), name);
}

// The 0.5 m base's file is today's defaults, key for key: copying it changes nothing.
TEST(RobotProfiles, BaseFileIsTheDefaults) {
  const nlohmann::json file = toJson(profile("base_0_5m.json"), true);
  const nlohmann::json defaults = toJson(SimConfig{}, true);
  for (const char* part : {"robot", "lidar", "encoders", "imu"})
    EXPECT_EQ(file[part], defaults[part]) << part;
}

TEST(RobotProfiles, TurtleBot3HasItsGeometryAndLidar) {
  const SimConfig c = profile("turtlebot3.json");
  EXPECT_DOUBLE_EQ(c.robot.geometry.radius_left_m, 0.033);
  EXPECT_DOUBLE_EQ(c.robot.geometry.radius_right_m, 0.033);
  EXPECT_DOUBLE_EQ(c.robot.geometry.wheel_base_m, 0.16);
  EXPECT_DOUBLE_EQ(c.lidar.rate_hz, 10.0);
  EXPECT_EQ(c.lidar.beams_per_revolution, 360);  // 1 degree beams
  EXPECT_DOUBLE_EQ(c.lidar.range_min_m, 0.12);
  EXPECT_DOUBLE_EQ(c.lidar.range_max_m, 3.5);
  // Small enough for a 4 m x 3 m room: the footprint disc is about 0.1 m, not 0.28 m.
  EXPECT_LT(footprintRadius(c.robot), 0.12);
}

// 20 s of the TurtleBot3 calibration drive (the figure eight) in the small room, physics: the
// light robot stays level (simulate throws when it tips), its true-geometry odometry follows the
// truth to slip, and its scans are 360 beams at 10 Hz with every return within 3.5 m.
TEST(RobotProfiles, TurtleBot3DrivesItsScenario) {
  SimConfig c = profile("turtlebot3.json");
  c.duration_s = 20.0;
  const World world = loadWorld(kWorlds / "small_room.yaml");
  const Scenario scenario = loadScenario(kWorlds / "scenarios" / "turtlebot3_calibration.yaml");
  const SimResult r = simulate(c, world, scenario);
  EXPECT_EQ(r.summary.scans, 200u);  // 10 Hz for 20 s: scan 199 ends before 20 s
  EXPECT_EQ(r.summary.beams, 200u * 360u);
  EXPECT_GT(r.summary.distance_m, 2.5);  // 0.15 m/s for most of 20 s
  EXPECT_LT(r.summary.drift_true.max_position_error_m, 0.005);
  for (const ScanRecord& s : r.dataset.scans)
    for (double range : s.scan.ranges_m)
      if (std::isfinite(range)) {
        ASSERT_GE(range, 0.12);
        ASSERT_LE(range, 3.5);
      }
}

}  // namespace
}  // namespace slamprep::sim
