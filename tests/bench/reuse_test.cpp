// Bench reuse and malformed results: a suite edited (physics to kinematic, methods added) and
// rerun reused every stored trial and mixed them into the new summary; a malformed baseline,
// summary or trial result ended in exit 1 with a raw JSON-library error, and --compare was read
// only after the whole suite ran.
#include <gtest/gtest.h>

#include <fstream>
#include <random>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/bench/bench.hpp"
#include "slamprep/eval/bench/runner.hpp"
#include "slamprep/eval/bench/summary.hpp"
#include "slamprep/tests/support/error_of.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::eval {
namespace {

namespace fs = std::filesystem;

TrialOutput seededTrial(const TrialSpec& spec) {
  std::mt19937_64 rng(spec.seed);
  return {{{"deskew", {{"none", {{"mean_m", std::uniform_real_distribution<>(0, 1)(rng)}}}}}},
          {{"seconds", 0.1}}};
}

using test::errorOf;

class Reuse : public ::testing::Test {
 protected:
  void SetUp() override {
    std::ofstream(scratch_ / "w.yaml") << "walls: [{from: [0, 0], to: [1, 0]}]\n";
    writeSuite("mode: physics\n");
  }
  void writeSuite(const std::string& extra) {
    std::ofstream(scratch_ / "reuse.yaml")
        << "name: reuse\nworlds: [" << (scratch_ / "w.yaml").string()
        << "]\nscenarios: [worlds/scenarios/arc.yaml]\nseeds: 3\ndeskew_methods: [none]\n"
        << extra;
  }
  BenchOptions options() const {
    BenchOptions o;
    o.suite = (scratch_ / "reuse.yaml").string();
    o.results_root = scratch_ / "results";
    o.jobs = 2;
    o.plots = false;
    o.progress = false;
    return o;
  }
  RunReport run() { return runBench(options(), seededTrial).run; }

  test::ScratchDir scratch_{"reuse"};
};

TEST_F(Reuse, AnEditedSuiteRecomputesInsteadOfMixing) {
  EXPECT_EQ(run().computed, 3u);
  EXPECT_EQ(run().reused, 3u);  // unchanged: resumed
  writeSuite("mode: kinematic\n");
  const RunReport kinematic = run();
  EXPECT_EQ(kinematic.computed, 3u);
  EXPECT_EQ(kinematic.reused, 0u);
  writeSuite("mode: kinematic\ncalibration_methods: [joint, ceres]\n");
  EXPECT_EQ(run().computed, 3u);
  writeSuite("mode: kinematic\ncalibration_methods: [joint, ceres]\ndeskew_geometry: true\n");
  EXPECT_EQ(run().computed, 3u);
}

TEST_F(Reuse, AnEditedWorldRecomputesItsTrials) {
  EXPECT_EQ(run().computed, 3u);
  std::ofstream(scratch_ / "w.yaml") << "walls: [{from: [0, 0], to: [2, 0]}]\n";
  EXPECT_EQ(run().computed, 3u);
}

TEST_F(Reuse, StaleResultsAreNeverSummarised) {
  EXPECT_EQ(run().computed, 3u);
  const fs::path trials_dir = scratch_ / "results" / "reuse" / "trials";
  Suite edited = loadSuite(scratch_ / "reuse.yaml");
  edited.mode = "kinematic";
  const TrialSet set = loadTrials(expandTrials(edited), trials_dir);
  EXPECT_TRUE(set.results.empty());
  EXPECT_EQ(set.missing.size(), 3u);
  EXPECT_EQ(set.stale.size(), 3u);
  // The input digests are not compared there: a merge needs no worlds.
  EXPECT_EQ(loadTrials(expandTrials(loadSuite(scratch_ / "reuse.yaml")), trials_dir).results.size(),
            3u);
}

TEST_F(Reuse, ABadBaselineIsRefusedBeforeAnyTrialRuns) {
  BenchOptions o = options();
  o.compare = scratch_ / "garbage.json";
  std::ofstream(*o.compare) << "{\"metrics\": [1,,]";
  EXPECT_NE(errorOf([&] { runBench(o, seededTrial); }).find("garbage.json:1: bad JSON"),
            std::string::npos);
  std::ofstream(*o.compare) << "{\"metrics\": {\"deskew/none/mean_m\": {\"mean\": \"low\"}}}";
  EXPECT_EQ(errorOf([&] { runBench(o, seededTrial); }),
            o.compare->string() + ": metrics.deskew/none/mean_m.mean: missing or not a number");
  EXPECT_FALSE(fs::exists(scratch_ / "results" / "reuse"));  // nothing ran, nothing written
}

TEST_F(Reuse, MalformedResultsNameTheFileAndField) {
  run();
  const fs::path dir = scratch_ / "results" / "reuse";
  const Suite suite = loadSuite(dir / "suite.yaml");
  const auto trials = expandTrials(suite);
  const fs::path first = dir / "trials" / (trials.front().id + ".json");
  writeFileAtomic(first, "{\"trial\": 5}");
  EXPECT_EQ(errorOf([&] { loadTrials(trials, dir / "trials"); }),
            first.string() + ": trial: missing or not an object (the trial's spec)");
  writeFileAtomic(first, "[1, 2");
  EXPECT_NE(errorOf([&] { loadTrials(trials, dir / "trials"); }).find(": bad JSON"),
            std::string::npos);

  const std::string summary = readFile(dir / "summary.json");
  nlohmann::json bad = nlohmann::json::parse(summary);
  bad["groups"][0]["world"] = 3;
  EXPECT_EQ(errorOf([&] { parseSuiteSummary(bad, "s.json"); }),
            "s.json: groups[0].world: missing or not a string");
  bad = nlohmann::json::parse(summary);
  bad["metrics"]["deskew/none/mean_m"]["n"] = -1;
  EXPECT_EQ(errorOf([&] { parseSuiteSummary(bad, "s.json"); }),
            "s.json: metrics.deskew/none/mean_m.n: missing or not a whole number >= 0");
  EXPECT_NO_THROW(parseSuiteSummary(nlohmann::json::parse(summary), "s.json"));
}

}  // namespace
}  // namespace slamprep::eval
