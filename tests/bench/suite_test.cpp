#include "slamprep/eval/bench/suite.hpp"

#include <gtest/gtest.h>

#include <fstream>

#include "slamprep/core/error.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::eval {
namespace {

// Into one folder per process, removed at exit.
std::filesystem::path writeTemp(const std::string& name, const std::string& text) {
  static const test::ScratchDir dir("suite");
  std::ofstream(dir / name) << text;
  return dir / name;
}

TEST(Suite, ExpandsWorldsScenariosSweepsAndSeeds) {
  const auto file = writeTemp("sweep.yaml", R"(
name: sweep
worlds: [worlds/room.yaml]
scenarios: [worlds/scenarios/arc.yaml, worlds/scenarios/spin.yaml]
set: {lidar.beams_per_revolution: 360}
sweep:
  lidar.rate_hz: [5, 10, 20]
seeds: 2
base_seed: 7
deskew_methods: [none, oracle]
)");
  const Suite suite = loadSuite(file);
  const auto trials = expandTrials(suite);
  ASSERT_EQ(trials.size(), 1u * 2 * 3 * 2);
  EXPECT_EQ(trials[0].id, "0000-room-arc-lidar.rate_hz=5-s7");
  EXPECT_EQ(trials[1].seed, 8u);
  EXPECT_EQ(trials[2].sweep.at("lidar.rate_hz"), "10");
  EXPECT_EQ(trials[11].overrides.at("lidar.beams_per_revolution"), "360");
  EXPECT_EQ(trials[11].scenario, "worlds/scenarios/spin.yaml");
  for (std::size_t i = 0; i < trials.size(); ++i) EXPECT_EQ(trials[i].index, i);
}

// Three axes of 1000 values made 10^9 trials, and bad_alloc after 32 s of
// expanding them. The product is refused when the suite is read, naming the key.
TEST(Suite, RefusesMoreTrialsThanTheLimitBeforeExpandingThem) {
  std::string values;
  for (int i = 0; i < 1000; ++i) values += (i ? ", " : "") + std::to_string(i * 1e-4);
  const auto file = writeTemp("huge.yaml", "worlds: [a]\nscenarios: [b]\nsweep:\n" +
                                               std::string("  lidar.range_noise_m: [") + values +
                                               "]\n  imu.gyro_noise_radps: [" + values +
                                               "]\n  imu.accel_noise_mps2: [" + values + "]\n");
  try {
    loadSuite(file);
    FAIL() << "accepted 10^9 trials";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), file.string() +
                                         ": sweep: worlds x scenarios x sweep points x seeds is "
                                         "1000000000 trials, more than the limit of 100000");
  }
  // At the limit exactly: read.
  EXPECT_NO_THROW(
      loadSuite(writeTemp("limit.yaml", "worlds: [a, b]\nscenarios: [c]\nseeds: 50000\n")));
  EXPECT_THROW(
      loadSuite(writeTemp("over.yaml", "worlds: [a, b, c]\nscenarios: [d]\nseeds: 50000\n")),
      InputError);
}

// The suite's settings travel with every trial, so an edited suite makes
// the stored results stale.
TEST(Suite, TrialsCarryTheSuiteSettings) {
  const Suite suite =
      loadSuite(writeTemp("settings.yaml",
                          "worlds: [a]\nscenarios: [b]\nmode: kinematic\n"
                          "calibration_methods: [joint]\ndeskew_methods: [none]\n"));
  const auto trials = expandTrials(suite);
  EXPECT_EQ(trials.front().settings["mode"], "kinematic");
  EXPECT_EQ(trials.front().settings["calibration_methods"], nlohmann::json::array({"joint"}));
  EXPECT_EQ(trials.front().settings["deskew_methods"], nlohmann::json::array({"none"}));
  Suite edited = suite;
  edited.mode = "physics";
  EXPECT_NE(expandTrials(edited).front().settings, trials.front().settings);
}

TEST(Suite, RejectsUnknownKeyWithFileAndLine) {
  const auto file = writeTemp("bad.yaml", "worlds: [a.yaml]\nscenarios: [b.yaml]\nseedz: 3\n");
  try {
    loadSuite(file);
    FAIL() << "accepted an unknown key";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad.yaml:3"), std::string::npos) << what;
    EXPECT_NE(what.find("seedz"), std::string::npos) << what;
  }
}

TEST(Suite, ReadsTheCalibrationSwitchesAndRefusesANonBoolean) {
  const std::string base = "worlds: [a]\nscenarios: [b]\n";
  const Suite defaults = loadSuite(writeTemp("k0.yaml", base));
  EXPECT_FALSE(defaults.calibration_sideslip);
  EXPECT_FALSE(defaults.calibration_loop_closure);
  EXPECT_TRUE(
      loadSuite(writeTemp("k1.yaml", base + "calibration_sideslip: true\n")).calibration_sideslip);
  EXPECT_TRUE(loadSuite(writeTemp("k2.yaml", base + "calibration_loop_closure: true\n"))
                  .calibration_loop_closure);
  for (const std::string key : {"calibration_sideslip", "calibration_loop_closure"}) {
    try {
      loadSuite(writeTemp("k3.yaml", base + key + ": maybe\n"));
      FAIL() << key << ": accepted 'maybe'";
    } catch (const InputError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("k3.yaml:3"), std::string::npos) << what;
      EXPECT_NE(what.find(key), std::string::npos) << what;
    }
  }
}

TEST(Suite, ReadsTolerancesWithTheirDirection) {
  const auto file = writeTemp("tol.yaml", R"(
worlds: [a.yaml]
scenarios: [b.yaml]
tolerances:
  deskew/none/mean_m: {abs: 0.001, rel: 0.05}
  calibration/joint/ok: {abs: 0.0, better: higher}
)");
  const Suite suite = loadSuite(file);
  ASSERT_EQ(suite.tolerances.size(), 2u);
  EXPECT_EQ(suite.tolerances[0].metric, "deskew/none/mean_m");
  EXPECT_DOUBLE_EQ(suite.tolerances[0].rel, 0.05);
  EXPECT_FALSE(suite.tolerances[0].higher_is_better);
  EXPECT_TRUE(suite.tolerances[1].higher_is_better);
  EXPECT_THROW(loadSuite(writeTemp("tol2.yaml",
                                   "worlds: [a]\nscenarios: [b]\ntolerances: {m: {better: up}}\n")),
               InputError);
}

TEST(Suite, RejectsBadValues) {
  EXPECT_THROW(loadSuite(writeTemp("s0.yaml", "worlds: [a]\nscenarios: [b]\nseeds: 0\n")),
               InputError);
  EXPECT_THROW(loadSuite(writeTemp("s1.yaml", "worlds: [a]\nscenarios: [b]\nmode: warp\n")),
               InputError);
  EXPECT_THROW(loadSuite(writeTemp("s2.yaml", "worlds: [a]\n")), InputError);
  EXPECT_THROW(loadSuite(writeTemp("s3.yaml", "worlds: [a\n")), InputError);
  EXPECT_THROW(loadSuite("/nonexistent/suite.yaml"), InputError);
  // A null key (found by fuzzing) is an input error, not a yaml-cpp exception.
  EXPECT_THROW(loadSuite(writeTemp("s7.yaml", "worlds: [a]\nscenarios: [b]\n~: 3\n")), InputError);
  // Unknown methods and simulator keys fail at load time, naming the key.
  EXPECT_THROW(
      loadSuite(writeTemp("s4.yaml", "worlds: [a]\nscenarios: [b]\ndeskew_methods: [warp]\n")),
      InputError);
  EXPECT_THROW(loadSuite(writeTemp("s5.yaml",
                                   "worlds: [a]\nscenarios: [b]\ncalibration_methods: [magic]\n")),
               InputError);
  try {
    loadSuite(writeTemp("s6.yaml", "worlds: [a]\nscenarios: [b]\nsweep: {lidar.rate_hzz: [5]}\n"));
    FAIL() << "accepted an unknown simulator key";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("lidar.rate_hzz"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace slamprep::eval
