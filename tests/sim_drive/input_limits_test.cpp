// Input limits of the simulator's inputs (docs/design.md "Input limits"): a second `walls:` block
// that used to be ignored, nesting and aliases that multiply a small file, worlds of 10^5 walls
// (quadratic set-up), scenario includes of /dev/zero or fanning out to 2^16 files, and sensor
// rates that ended in bad_alloc. Each is an InputError naming the file (line) or the key.
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "slamprep/core/error.hpp"
#include "slamprep/core/input_file.hpp"
#include "slamprep/sim/drive/config.hpp"
#include "slamprep/sim/drive/scenario.hpp"
#include "slamprep/sim/physics/world.hpp"
#include "slamprep/sim/yaml/yaml_fields.hpp"
#include "slamprep/tests/support/error_of.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::sim {
namespace {

using test::errorOf;

class YamlLimits : public ::testing::Test {
 protected:
  std::string worldError(const std::string& yaml) {
    const auto file = scratch_ / "w.yaml";
    std::ofstream(file) << yaml;
    return errorOf([&] { loadWorld(file); });
  }
  std::string file() const { return (scratch_ / "w.yaml").string(); }

  test::ScratchDir scratch_{"yaml_limits"};
};

constexpr const char* kWall = "  - {from: [0, 0], to: [1, 0]}\n";

TEST_F(YamlLimits, SecondWallsBlockIsRefusedNamingBothLines) {
  const std::string yaml = std::string("name: w\nwalls:\n") + kWall + "walls:\n" + kWall;
  EXPECT_EQ(worldError(yaml),
            file() + ":4:1: walls: key appears twice in one mapping (first on line 2)");
  // Nested mappings too.
  EXPECT_EQ(worldError(std::string("walls:\n  - {from: [0, 0], to: [1, 0], to: [2, 0]}\n")),
            file() + ":2:32: to: key appears twice in one mapping (first on line 2)");
}

TEST_F(YamlLimits, NestingBeyondTheLimitIsRefused) {
  const std::string deep = std::string(kMaxYamlDepth, '[') + std::string(kMaxYamlDepth, ']');
  EXPECT_NE(worldError("walls: " + deep + "\n").find("YAML nested deeper than 64 levels"),
            std::string::npos);
}

TEST_F(YamlLimits, AliasesThatMultiplyAreCounted) {
  // 10^9 uses of one node from 600 bytes ("billion laughs").
  std::string yaml = "a0: &a0 [x, x, x, x, x, x, x, x, x, x]\n";
  for (int i = 1; i < 10; ++i) {
    // Appended piecewise: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
    yaml.append("a")
        .append(std::to_string(i))
        .append(": &a")
        .append(std::to_string(i))
        .append(" [");
    for (int k = 0; k < 10; ++k) yaml.append(k ? ", *a" : "*a").append(std::to_string(i - 1));
    yaml += "]\n";
  }
  EXPECT_EQ(worldError(yaml + "walls: *a9\n"),
            file() + ": more than 1000000 YAML nodes (aliases count every time they are used)");
}

TEST_F(YamlLimits, MoreObjectsThanTheLimitAreRefusedBeforeParsingThem) {
  std::string yaml = "walls:\n";
  for (int i = 0; i < 6000; ++i) yaml += kWall;
  yaml += "boxes:\n";
  for (int i = 0; i < 4001; ++i) yaml += "  - {center: [0, 0], size: [1, 1]}\n";
  EXPECT_EQ(worldError(yaml), file() +
                                  ":6003:3: boxes: the world has more than 10000 objects "
                                  "(walls, boxes, cylinders, polygons and floor patches "
                                  "together)");
}

TEST_F(YamlLimits, DevicesAndLargeFilesAreRefusedUnread) {
  EXPECT_EQ(errorOf([] { loadWorld("/dev/zero"); }),
            "/dev/zero: cannot read world file: a character device, not a regular file");
  EXPECT_NE(worldError("# " + std::string(kMaxYamlFileBytes, 'x') + "\n")
                .find("is larger than the limit of 512 KiB"),
            std::string::npos);
}

TEST(ScenarioLimits, IncludeOfADeviceIsRefusedNamingTheIncluder) {
  const test::ScratchDir dir("scenario_limits");
  std::ofstream(dir / "zero.yaml") << "segments:\n  - {type: include, file: /dev/zero}\n";
  const std::string msg = errorOf([&] { loadScenario(dir / "zero.yaml"); });
  EXPECT_NE(msg.find("include: /dev/zero: cannot read scenario file: a character device"),
            std::string::npos)
      << msg;
}

TEST(ScenarioLimits, IncludeFanOutIsBounded) {
  // Each file includes the next twice: 2^10 loads of 11 small files, within the depth limit.
  const test::ScratchDir dir("scenario_fanout");
  for (int k = 0; k < 10; ++k) {
    const std::string next =
        std::string("  - {type: include, file: f").append(std::to_string(k + 1)).append(".yaml}\n");
    std::ofstream(dir / std::string("f").append(std::to_string(k)).append(".yaml")) << "segments:\n"
                                                                                    << next << next;
  }
  std::ofstream(dir / "f10.yaml") << "segments:\n  - {type: stop, duration_s: 0.1}\n";
  const std::string msg = errorOf([&] { loadScenario(dir / "f0.yaml"); });
  EXPECT_NE(msg.find("includes more than 256 scenario files in all"), std::string::npos) << msg;
  // Eight loads are well within it.
  EXPECT_NO_THROW(loadScenario(dir / "f7.yaml"));
}

TEST(ConfigLimits, SensorAndFaultRatesBeyondAnySensorAreRefused) {
  const auto refusal = [](const std::string& assignment) {
    SimConfig config;
    return errorOf([&] { applyOverride(config, assignment); });
  };
  EXPECT_EQ(refusal("lidar.rate_hz=1e9"), "--set: lidar.rate_hz: must be at most 100 (got 1e+09)");
  EXPECT_EQ(refusal("imu.rate_hz=20000"), "--set: imu.rate_hz: must be at most 10000 (got 20000)");
  EXPECT_EQ(refusal("encoders.rate_hz=1e5"),
            "--set: encoders.rate_hz: must be at most 10000 (got 100000)");
  EXPECT_NE(refusal("faults.held_robot.rate_hz=1e9").find("must be at most 100"),
            std::string::npos);
  EXPECT_EQ(refusal("lidar.rate_hz=40"), "");
  EXPECT_EQ(refusal("encoders.slip_sigma=0.6"),
            "--set: encoders.slip_sigma: must be in [0, 0.5] (got 0.6)");
  EXPECT_NE(refusal("encoders.slip_tau_s=0").find("encoders.slip_tau_s"), std::string::npos);
  EXPECT_EQ(refusal("encoders.slip_sigma=0.05"), "");
}

TEST(ConfigLimits, RunsTooLargeToHoldAreRefusedBeforeSimulating) {
  SimConfig config;
  EXPECT_NO_THROW(checkRunSize(config, 86400.0));  // a day at the defaults fits
  applyOverride(config, "physics_rate_hz=100000");
  EXPECT_EQ(errorOf([&] { checkRunSize(config, 86400.0); }).rfind("physics_rate_hz: a run of", 0),
            0u);
  SimConfig beams;
  applyOverride(beams, "lidar.rate_hz=100");
  applyOverride(beams, "lidar.beams_per_revolution=100000");
  EXPECT_NE(errorOf([&] {
              checkRunSize(beams, 3600.0);
            }).find("lidar.rate_hz x lidar.beams_per_revolution"),
            std::string::npos);
}

}  // namespace
}  // namespace slamprep::sim
