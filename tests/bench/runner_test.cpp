#include "slamprep/eval/bench/runner.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/stage_report.hpp"
#include "slamprep/eval/bench/summary.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::eval {
namespace {

namespace fs = std::filesystem;

// A stand-in trial: numbers drawn from the seed alone, like a real trial's results.
TrialOutput fakeTrial(const TrialSpec& spec) {
  std::mt19937_64 rng(spec.seed * 1000 + spec.index);
  std::normal_distribution<double> noise(0.0, 1.0);
  if (spec.scenario == "explode.yaml") throw std::runtime_error("boom");
  return {{{"deskew",
            {{"none", {{"mean_m", 0.19 + 0.01 * noise(rng)}}},
             {"oracle", {{"mean_m", 1e-6 * std::abs(noise(rng))}}}}},
           {"calibration",
            {{"joint", {{"ok", true}, {"abs_error_rel", {{"b", 1e-4 * std::abs(noise(rng))}}}}}}}},
          {{"seconds", 0.5}}};
}

Suite fakeSuite() {
  Suite suite;
  suite.name = "fake";
  suite.worlds = {"room.yaml"};
  suite.scenarios = {"arc.yaml", "spin.yaml"};
  suite.sweep = {{"lidar.rate_hz", {"5", "10", "20"}}};
  suite.seeds = 2;
  return suite;
}

std::string runToSummary(const Suite& suite, const fs::path& dir, int jobs, Shard shard = {}) {
  const auto trials = expandTrials(suite);
  runTrials(trials, fakeTrial, {jobs, shard, dir / "trials", dir / "timing", false});
  return nlohmann::json(summarize(suite, loadTrials(trials, dir / "trials"))).dump(2);
}

TEST(Runner, SameBytesWhateverTheJobCount) {
  const Suite suite = fakeSuite();
  const test::ScratchDir scratch("runner");
  const std::string one = runToSummary(suite, scratch / "jobs1", 1);
  const std::string two = runToSummary(suite, scratch / "jobs2", 2);
  EXPECT_EQ(one, two);
  const auto trials = expandTrials(suite);
  for (const auto& t : trials)
    EXPECT_EQ(readFile(scratch / "jobs1" / "trials" / (t.id + ".json")),
              readFile(scratch / "jobs2" / "trials" / (t.id + ".json")));
}

// Stage reports travel to the parent (on stderr here) and never into the result files.
TEST(Runner, StageReportsLeaveTheResultsAlone) {
  const Suite suite = fakeSuite();
  const auto trials = expandTrials(suite);
  const TrialFunction reporting = [](const TrialSpec& spec) {
    StageReporter stages(spec.id, 2);
    stages.begin("simulate");
    for (int i = 0; i <= 10; ++i) stages.update(i / 10.0);
    stages.begin("deskew");
    return fakeTrial(spec);
  };
  const test::ScratchDir scratch("runner");
  const fs::path shown = scratch / "progress_shown", quiet = scratch / "progress_quiet";
  const RunReport a =
      runTrials(trials, reporting, {2, {}, shown / "trials", shown / "timing", true});
  runTrials(trials, fakeTrial, {1, {}, quiet / "trials", quiet / "timing", false});
  EXPECT_EQ(a.computed, trials.size());
  for (const auto& t : trials)
    EXPECT_EQ(readFile(shown / "trials" / (t.id + ".json")),
              readFile(quiet / "trials" / (t.id + ".json")));
}

TEST(Runner, ShardsMergeToTheSingleRun) {
  const Suite suite = fakeSuite();
  const auto trials = expandTrials(suite);
  const test::ScratchDir scratch("runner");
  const std::string single = runToSummary(suite, scratch / "single", 2);
  const fs::path base = scratch / "sharded";
  std::vector<fs::path> shard_dirs;
  std::size_t selected = 0;
  for (int k = 1; k <= 3; ++k) {
    const fs::path dir = base / ("shard" + std::to_string(k));
    const auto report =
        runTrials(trials, fakeTrial, {1, {k, 3}, dir / "trials", dir / "timing", false});
    selected += report.selected;
    shard_dirs.push_back(dir / "trials");
  }
  EXPECT_EQ(selected, trials.size());  // disjoint and complete
  EXPECT_EQ(mergeTrialFolders(shard_dirs, base / "merged"), trials.size());
  EXPECT_EQ(nlohmann::json(summarize(suite, loadTrials(trials, base / "merged"))).dump(2), single);
}

TEST(Runner, ResumesWithoutRecomputingFinishedTrials) {
  const Suite suite = fakeSuite();
  const auto trials = expandTrials(suite);
  const test::ScratchDir scratch("runner");
  const fs::path dir = scratch / "resume";
  RunOptions options{2, {}, dir / "trials", dir / "timing", false};
  EXPECT_EQ(runTrials(trials, fakeTrial, options).computed, trials.size());
  fs::remove(dir / "trials" / (trials[3].id + ".json"));
  const auto again = runTrials(trials, fakeTrial, options);
  EXPECT_EQ(again.computed, 1u);
  EXPECT_EQ(again.reused, trials.size() - 1);
}

TEST(Runner, ReportsFailedTrialsAndWritesNoResultForThem) {
  Suite suite = fakeSuite();
  suite.scenarios = {"arc.yaml", "explode.yaml"};
  suite.sweep.clear();
  suite.seeds = 1;
  const auto trials = expandTrials(suite);
  const test::ScratchDir scratch("runner");
  const fs::path dir = scratch / "failing";
  const auto report = runTrials(trials, fakeTrial, {2, {}, dir / "trials", dir / "timing", false});
  ASSERT_EQ(report.failed.size(), 1u);
  EXPECT_EQ(report.failed[0], trials[1].id);
  EXPECT_FALSE(fs::exists(dir / "trials" / (trials[1].id + ".json")));
  EXPECT_EQ(loadTrials(trials, dir / "trials").missing, std::vector<std::string>{trials[1].id});
}

TEST(Shard, ParsesAndRejects) {
  const Shard s = Shard::parse("2/8");
  EXPECT_EQ(s.index, 2);
  EXPECT_EQ(s.count, 8);
  EXPECT_TRUE(s.contains(9));
  EXPECT_FALSE(s.contains(8));
  for (const char* bad : {"0/3", "4/3", "2", "a/b", "1/0", "1/2x"})
    EXPECT_THROW(Shard::parse(bad), std::exception) << bad;
}

TEST(Compare, FlagsOnlyMetricsWorseThanTheirTolerance) {
  const std::map<std::string, double> baseline = {{"a", 1.0}, {"b", 0.001}};
  SuiteSummary current;
  current.metrics = {{"a", {.mean = 1.05}}, {"b", {.mean = 0.0021}}};
  const std::vector<Tolerance> tol = {
      {"a", 0.0, 0.1}, {"b", 0.001, 0.0}, {"c", 1.0, 0.0}, {"a", 0.0, 0.01, true}};
  const auto regressions = compareToBaseline(current, baseline, tol);
  ASSERT_EQ(regressions.size(), 2u);
  EXPECT_EQ(regressions[0].metric, "b");
  EXPECT_NEAR(regressions[0].allowed, 0.002, 1e-15);
  EXPECT_EQ(regressions[1].metric, "c");  // missing counts as a regression
  // Higher is better: a drop beyond the slack regresses, a rise never does.
  SuiteSummary lower;
  lower.metrics = {{"a", {.mean = 0.98}}};
  const auto drop = compareToBaseline(lower, baseline, {{"a", 0.0, 0.01, true}});
  ASSERT_EQ(drop.size(), 1u);
  EXPECT_NEAR(drop[0].allowed, 0.99, 1e-15);
}

}  // namespace
}  // namespace slamprep::eval

namespace slamprep::eval {
namespace {

// One trial result of group (world, scenario): joint's signed r_L error and sigma, and a NEES.
nlohmann::json consistencyTrial(const std::string& world, bool ok, double error, double sigma,
                                double nees) {
  nlohmann::json joint = {{"ok", ok}};
  if (ok)
    joint.update(
        {{"signed_error", {{"r_L_pct", error}}}, {"sigma", {{"r_L_pct", sigma}}}, {"nees", nees}});
  return {
      {"trial", {{"world", world}, {"scenario", "s.yaml"}, {"sweep", nlohmann::json::object()}}},
      {"calibration", {{"joint", joint}}}};
}

TEST(Summary, ConsistencyPerGroupOverTheTrialsThatDidNotRefuse) {
  TrialSet set;
  for (const auto& [e, n] : {std::pair{1.0, 4.0}, {-2.0, 8.0}, {0.5, 5.0}, {3.0, 7.0}})
    set.results.push_back(consistencyTrial("a.yaml", true, e, 1.0, n));
  set.results.push_back(consistencyTrial("a.yaml", false, 0, 0, 0));       // refused: left out
  set.results.push_back(consistencyTrial("b.yaml", true, 0.1, 2.0, 1.0));  // another group
  Suite suite;
  suite.name = "s";
  const SuiteSummary summary = summarize(suite, set);
  ASSERT_EQ(summary.groups.size(), 2u);
  ASSERT_TRUE(summary.groups[0].consistency.contains("joint"));
  const MethodConsistency& c = summary.groups[0].consistency.at("joint");
  ASSERT_TRUE(c.params.contains(CalibrationParam::kRL));
  const ErrorConsistency& r_L = c.params.at(CalibrationParam::kRL);
  EXPECT_EQ(r_L.n, 4);
  EXPECT_DOUBLE_EQ(r_L.bias, 0.625);
  EXPECT_DOUBLE_EQ(r_L.rms, std::sqrt(14.25 / 4));
  EXPECT_DOUBLE_EQ(r_L.coverage_1sigma, 0.5);
  EXPECT_DOUBLE_EQ(r_L.coverage_3sigma, 1.0);
  ASSERT_TRUE(c.nees);
  EXPECT_DOUBLE_EQ(c.nees->mean, 6.0);  // (4 + 8 + 5 + 7) / 4
  EXPECT_EQ(c.nees->n, 4u);
  EXPECT_FALSE(c.params.contains(CalibrationParam::kMountX));  // no sigma reported for it
  EXPECT_DOUBLE_EQ(
      summary.groups[1].consistency.at("joint").params.at(CalibrationParam::kRL).coverage_1sigma,
      1.0);
  // In summary.json: flat keys under the group's "consistency", the counts as whole numbers.
  const nlohmann::json written = summary;
  const std::string p = "calibration/joint/consistency/";
  EXPECT_EQ(written["groups"][0]["consistency"][p + "r_L/n"].dump(), "4");
  EXPECT_EQ(written["groups"][0]["consistency"][p + "nees_n"].dump(), "4");
  EXPECT_EQ(written["groups"][0]["consistency"][p + "r_L/bias"], 0.625);
}

}  // namespace
}  // namespace slamprep::eval
