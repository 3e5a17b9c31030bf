#include "slamprep/sim/drive/config.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <string_view>

#include "slamprep/core/error.hpp"

namespace slamprep::sim {
namespace {

std::string overrideError(const std::string& assignment) {
  SimConfig config;
  try {
    applyOverride(config, assignment);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(SimConfig, DefaultsMatchTheSpec) {
  const SimConfig c;
  EXPECT_EQ(c.physics_rate_hz, 1000.0);
  EXPECT_EQ(c.encoders.ticks_per_revolution, 4096);
  EXPECT_EQ(c.encoders.rate_hz, 100.0);
  EXPECT_EQ(c.imu.rate_hz, 200.0);
  const DiffDriveParams nominal = c.nominalGeometry();
  EXPECT_NEAR(nominal.radius_left_m, c.robot.geometry.radius_left_m * 1.02, 1e-15);
  EXPECT_NEAR(nominal.radius_right_m, c.robot.geometry.radius_right_m * 0.985, 1e-15);
  EXPECT_NEAR(nominal.wheel_base_m, c.robot.geometry.wheel_base_m * 1.04, 1e-15);
  EXPECT_NO_THROW(validate(c, "defaults"));
}

TEST(SimConfig, OverridesSetFieldsByDottedKey) {
  SimConfig c;
  applyOverride(c, "lidar.rate_hz=5");
  applyOverride(c, "robot.radius_left_m=0.11");
  applyOverride(c, "nominal.radius_left_error=0.03");
  applyOverride(c, "encoders.ticks_per_revolution=1024");
  applyOverride(c, "lidar.clockwise=true");
  applyOverride(c, "mode=kinematic");
  applyOverride(c, "seed=18446744073709551615");
  applyOverride(c, "scenario=a=b.yaml");  // only the first '=' splits
  EXPECT_EQ(c.lidar.rate_hz, 5.0);
  EXPECT_EQ(c.robot.geometry.radius_left_m, 0.11);
  EXPECT_EQ(c.nominal.radius_left_error, 0.03);
  EXPECT_EQ(c.encoders.ticks_per_revolution, 1024);
  EXPECT_TRUE(c.lidar.clockwise);
  EXPECT_EQ(c.mode, SimMode::kinematic);
  EXPECT_EQ(c.seed, 18446744073709551615ULL);
  EXPECT_EQ(c.scenario, "a=b.yaml");
}

TEST(SimConfig, BadOverridesNameTheKey) {
  const std::string unknown = overrideError("lidar.rate=5");
  EXPECT_NE(unknown.find("--set lidar.rate"), std::string::npos) << unknown;
  EXPECT_NE(unknown.find("unknown"), std::string::npos);
  EXPECT_NE(overrideError("lidar").find("key=value"), std::string::npos);
  EXPECT_NE(overrideError("lidar.rate_hz=fast").find("--set lidar.rate_hz"), std::string::npos);
  EXPECT_NE(overrideError("lidar.rate_hz=nan").find("finite"), std::string::npos);
  EXPECT_NE(overrideError("encoders.ticks_per_revolution=1.5").find("whole number"),
            std::string::npos);
  EXPECT_NE(overrideError("mode=fast").find("physics"), std::string::npos);
  const std::string negative = overrideError("robot.radius_left_m=-0.1");
  EXPECT_NE(negative.find("robot.radius_left_m"), std::string::npos) << negative;
  EXPECT_NE(negative.find("positive"), std::string::npos);
  EXPECT_NE(overrideError("lidar.beams_per_revolution=0").find("lidar.beams_per_revolution"),
            std::string::npos);
  EXPECT_NE(overrideError("lidar.fov_rad=0.001").find("lidar.fov_rad"), std::string::npos);
  // A revolution longer than the scans' period (10 Hz by default) would overlap the next scan.
  EXPECT_NE(overrideError("lidar.sweep_s=0.2").find("lidar.sweep_s"), std::string::npos);
  EXPECT_NE(overrideError("lidar.sweep_s=-0.01").find("lidar.sweep_s"), std::string::npos);
  EXPECT_NE(overrideError("nominal.wheel_base_error=-1").find("nominal.wheel_base_error"),
            std::string::npos);
  for (const char* bad : {"lidar.range_noise_fixed_m=-0.01", "lidar.range_noise_fixed_length_m=0",
                          "encoders.common_slip_sigma=0.6", "nominal.lidar_mount_error.x_m=nan",
                          "lidar.range_bias_by_beam_m=0.01,x", "lidar.range_bias_by_beam_m=2",
                          "lidar.range_bias_by_range_m=0,inf", "people.count=-1", "people.count=21",
                          "people.radius_m=0", "people.correlation_s=0"}) {
    const std::string key(bad, std::string_view(bad).find('='));
    EXPECT_NE(overrideError(bad).find(key), std::string::npos) << overrideError(bad);
  }
  // A failed override leaves the configuration untouched.
  SimConfig c;
  EXPECT_THROW(applyOverride(c, "robot.wheel_base_m=0"), InputError);
  EXPECT_EQ(c.robot.geometry.wheel_base_m, SimConfig{}.robot.geometry.wheel_base_m);
}

TEST(SimConfig, JsonRoundTripsEveryKey) {
  SimConfig c;
  applyOverride(c, "lidar.mount.yaw_rad=-0.25");
  applyOverride(c, "imu.gyro_bias_radps=0.004");
  applyOverride(c, "seed=77");
  applyOverride(c, "mode=kinematic");
  applyOverride(c, "faults.enable=clock_offset");  // the fault keys are written only with one on
  applyOverride(c, "start_jitter.yaw_deg=30");     // and the start_jitter keys only when it is on
  applyOverride(c, "odometry.heading_from=gyro");  // and the odometry key only when it is gyro
  applyOverride(c, "people.count=2");              // and the people keys only with people
  const nlohmann::json json = toJson(c);
  EXPECT_EQ(json["lidar"]["mount"]["yaw_rad"], -0.25);
  EXPECT_EQ(json["odometry"]["heading_from"], "gyro");
  EXPECT_EQ(json.flatten().size(), configKeys().size());
  const SimConfig back = configFromJson(json, "dataset.json: config");
  EXPECT_EQ(toJson(back), json);
  EXPECT_EQ(back.mode, SimMode::kinematic);
  EXPECT_EQ(back.seed, 77u);
  EXPECT_EQ(back.odometry.heading_from, OdometryHeading::gyro);
  EXPECT_THROW(applyOverride(c, "odometry.heading_from=compass"), InputError);
}

TEST(SimConfig, JsonRejectsUnknownKeysAndWrongTypes) {
  nlohmann::json json = toJson(SimConfig{});
  json["lidar"]["beams"] = 5;
  try {
    configFromJson(json, "cfg.json");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cfg.json: lidar.beams"), std::string::npos) << e.what();
  }
  json = toJson(SimConfig{});
  json["encoders"]["rate_hz"] = "fast";
  EXPECT_THROW(configFromJson(json, "cfg.json"), InputError);
  // Missing keys keep their defaults.
  EXPECT_EQ(configFromJson(nlohmann::json::object(), "cfg.json").lidar.rate_hz, 10.0);
}

// Off, the start is the world's; on, each seed moves it by its own draw within the bounds, the
// same draw every time, and 100 seeds spread over the whole range (each half hit at least once).
TEST(SimConfig, StartJitterMovesTheStartPerSeedWithinItsBounds) {
  SimConfig c;
  const SE2 world_start(5.0, 4.0, 0.3);
  EXPECT_EQ(c.startPose(world_start).translation(), world_start.translation());
  EXPECT_FALSE(toJson(c).contains("start_jitter"));
  applyOverride(c, "start_jitter.position_m=0.25");
  applyOverride(c, "start_jitter.yaw_deg=180");
  bool left = false, right = false, turned_left = false, turned_right = false;
  for (std::uint64_t seed = 1; seed <= 100; ++seed) {
    c.seed = seed;
    const SE2 start = c.startPose(world_start);
    EXPECT_EQ(start.x, c.startPose(world_start).x);
    EXPECT_LE(std::abs(start.x - 5.0), 0.25);
    EXPECT_LE(std::abs(start.y - 4.0), 0.25);
    (start.x < 5.0 ? left : right) = true;
    (normalizeAngle(start.yaw - 0.3) < 0.0 ? turned_right : turned_left) = true;
  }
  EXPECT_TRUE(left && right && turned_left && turned_right);
  EXPECT_NE(overrideError("start_jitter.yaw_deg=181"), "");
  EXPECT_NE(overrideError("start_jitter.position_m=-1"), "");
}

TEST(SimConfig, FootprintCoversChassisAndWheels) {
  const RobotConfig r;
  // Chassis 0.40 x 0.36: half diagonal 0.269; wheels reach (0.1, 0.265): 0.283.
  EXPECT_NEAR(footprintRadius(r), std::hypot(0.1, 0.265), 1e-12);
}

}  // namespace
}  // namespace slamprep::sim
