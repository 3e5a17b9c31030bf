// End-to-end: the `slamprep simulate` command, its exit codes and messages, and that a refused
// run leaves nothing behind.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "slamprep/tests/support/cli_run.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace {

namespace fs = std::filesystem;

using slamprep::test::CliRun;
using slamprep::test::slurp;

class SimulateCommand : public ::testing::Test {
 protected:
  /// `slamprep simulate ARGS --quiet --out DIR/data`.
  CliRun simulate(std::vector<std::string> args) {
    args.insert(args.begin(), "simulate");
    args.insert(args.end(), {"--quiet", "--out", (dir_ / "data").string()});
    return slamprep::test::runSlamprep(args, dir_);
  }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  /// The refused run must leave neither the dataset nor a temporary sibling.
  void expectNothingWritten() {
    for (const auto& entry : fs::directory_iterator(dir_)) {
      const std::string name = entry.path().filename().string();
      EXPECT_TRUE(name == "stdout" || name == "stderr" || name.ends_with(".yaml")) << name;
    }
  }

  const slamprep::test::ScratchDir scratch_{"simulate_cli"};
  const fs::path dir_ = scratch_.path();
};

TEST_F(SimulateCommand, DefaultsRunAndPrintASummary) {
  const CliRun run = simulate({"--duration", "1", "--mode", "kinematic"});
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_TRUE(fs::exists(dir_ / "data" / "dataset.json"));
  EXPECT_TRUE(fs::exists(dir_ / "data" / "scans.jsonl"));
  EXPECT_NE(run.out.find("real time"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("nominal geometry"), std::string::npos) << run.out;
  EXPECT_NE(run.out.find("scans 10"), std::string::npos) << run.out;
  // The config it ran with is in dataset.json, default world and scenario included.
  const std::string json = slurp(dir_ / "data" / "dataset.json");
  EXPECT_NE(json.find("worlds/room.yaml"), std::string::npos);
  EXPECT_NE(json.find("worlds/scenarios/default.yaml"), std::string::npos);
}

TEST_F(SimulateCommand, MalformedScenarioNamesFileAndLine) {
  const fs::path bad = write("bad.yaml", "segments:\n  - {type: straight, distance_m: [1\n");
  const CliRun run = simulate({"--scenario", bad.string()});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find(bad.string() + ":"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("malformed YAML"), std::string::npos) << run.err;
  expectNothingWritten();
}

TEST_F(SimulateCommand, UnknownKeyIsNamed) {
  const CliRun run = simulate({"--set", "lidar.rat_hz=5"});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("lidar.rat_hz"), std::string::npos) << run.err;
  expectNothingWritten();
}

TEST_F(SimulateCommand, NegativeRadiusIsNamed) {
  const CliRun run = simulate({"--set", "robot.radius_right_m=-0.1"});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("robot.radius_right_m"), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("positive"), std::string::npos) << run.err;
  expectNothingWritten();
}

TEST_F(SimulateCommand, ZeroBeamsIsNamed) {
  const CliRun run = simulate({"--set", "lidar.beams_per_revolution=0"});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("lidar.beams_per_revolution"), std::string::npos) << run.err;
  expectNothingWritten();
}

TEST_F(SimulateCommand, ScenarioTooLongForTheWorldIsRefused) {
  const fs::path far = write("far.yaml",
                             "segments:\n  - {type: spin, angle_deg: 30}\n"
                             "  - {type: straight, distance_m: 20, speed_mps: 1.0}\n");
  const CliRun run = simulate({"--scenario", far.string()});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find(far.string() + ":3: segments[1] (straight)"), std::string::npos)
      << run.err;
  EXPECT_NE(run.err.find("free space"), std::string::npos) << run.err;
  expectNothingWritten();
}

TEST_F(SimulateCommand, MissingWorldFileIsNamed) {
  const CliRun run = simulate({"--world", "nowhere.yaml"});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("nowhere.yaml"), std::string::npos) << run.err;
  expectNothingWritten();
}

}  // namespace
