// `slamprep score relations|ape|rpe` end to end on small files written here: figures, JSON keys,
// and exit status 2 with file and line for bad input.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slamprep/tests/support/cli_run.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace {

namespace fs = std::filesystem;

using slamprep::test::CliRun;
using slamprep::test::slurp;

// One folder per process, removed at exit: the tests of a process share it.
fs::path dir() {
  static const slamprep::test::ScratchDir d("score_cli");
  return d.path();
}

std::string write(const std::string& name, const std::string& text) {
  std::ofstream(dir() / name) << text;
  return (dir() / name).string();
}

CliRun cli(const std::vector<std::string>& args) {
  return slamprep::test::runSlamprep(args, dir());
}

// A straight drive along x at 1 m/s, 1 Hz, for 10 s (yaw 0: quaternion 0 0 0 1).
std::string straightTum(double x_offset) {
  std::string text = "# t x y z qx qy qz qw\n";
  for (int k = 0; k <= 10; ++k)
    text += std::to_string(k) + " " + std::to_string(k + x_offset) + " 0 0 0 0 0 1\n";
  return text;
}

class ScoreCommand : public ::testing::Test {};

TEST_F(ScoreCommand, RelationsOfTheTrajectoryItselfScoreZeroAndAShortfallShows) {
  const std::string traj = write("traj.tum", straightTum(0.0));
  // 1 m per second: relations 1 s (short) and 8 s apart, the last one 0.1 m short of the truth.
  const std::string rel = write(
      "r.relations", "0 1 1 0 0 0 0 0\n2 3 1 0 0 0 0 0\n1 9 7.9 0 0 0 0 0\n20 21 1 0 0 0 0 0\n");
  const std::string json = (dir() / "r.json").string();
  const CliRun r = cli({"score", "relations", rel, traj, "--json", json});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("4 relations in " + rel + ": 3 scored, 1 skipped"), std::string::npos)
      << r.out;
  EXPECT_NE(r.out.find("translation [m]"), std::string::npos);
  const auto j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["scored"], 3);
  EXPECT_EQ(j["uncovered"], 1);
  EXPECT_EQ(j["short_scored"], 2);
  EXPECT_NEAR(j["all"]["translation_m"]["max"].get<double>(), 0.1, 1e-12);
  EXPECT_NEAR(j["all"]["translation_m"]["mean"].get<double>(), 0.1 / 3, 1e-12);
  EXPECT_NEAR(j["all"]["translation_sq_m2"]["mean"].get<double>(), 0.01 / 3, 1e-12);
  EXPECT_EQ(j["short"]["translation_m"]["max"].get<double>(), 0.0);
  EXPECT_EQ(j["all"]["rotation_deg"]["max"].get<double>(), 0.0);
}

TEST_F(ScoreCommand, BadInputExitsTwoNamingFileAndLine) {
  const std::string traj = write("ok.tum", straightTum(0.0));
  const std::string bad_rel = write("bad.relations", "0 1 1 0 0 0 0 0\n# c\n0 1 1 0 0 0 0\n");
  CliRun r = cli({"score", "relations", bad_rel, traj});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(bad_rel + ":3: expected 8 columns"), std::string::npos) << r.err;
  const std::string bad_tum =
      write("bad.tum", "0 0 0 0 0 0 0 1\n1 1 0 0 0 0 0 1\n0.5 1 0 0 0 0 0 1\n");
  r = cli({"score", "ape", traj, bad_tum});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(bad_tum + ":3: t:"), std::string::npos) << r.err;
  const std::string rel = write("ok.relations", "0 1 1 0 0 0 0 0\n");
  r = cli({"score", "relations", rel, (dir() / "missing.tum").string()});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing.tum"), std::string::npos) << r.err;
}

// Paths reach the command as one word each: a name the shell would split, expand or run.
TEST_F(ScoreCommand, PathsWithShellCharactersArePassedAsTheyAre) {
  const std::string traj = write("it's a $HOME; trajectory`x`.tum", straightTum(0.0));
  const std::string rel = write("r \"1\".relations", "0 1 1 0 0 0 0 0\n");
  const CliRun r = cli({"score", "relations", rel, traj});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("1 relations in " + rel + ": 1 scored, 0 skipped"), std::string::npos)
      << r.out;
  EXPECT_TRUE(fs::exists(dir() / "it's a $HOME; trajectory`x`.tum"));
}

TEST_F(ScoreCommand, ApeAndRpeOfAShiftedCopy) {
  const std::string gt = write("gt.tum", straightTum(0.0));
  const std::string est = write("est.tum", straightTum(0.25));
  const std::string json = (dir() / "ape.json").string();
  CliRun r = cli({"score", "ape", gt, est, "--align", "none", "--json", json});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  auto j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["matched"], 11);
  EXPECT_NEAR(j["translation_m"]["mean"].get<double>(), 0.25, 1e-12);
  r = cli({"score", "ape", gt, est, "--json", json});  // an existing --json: refused
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--force"), std::string::npos) << r.err;
  r = cli({"score", "ape", gt, est, "--force", "--json", json});  // rigid alignment removes it
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_LT(nlohmann::json::parse(slurp(json))["translation_m"]["max"].get<double>(), 1e-9);
  r = cli({"score", "rpe", gt, est, "--delta", "2", "--force", "--json", json});
  ASSERT_EQ(r.exit_code, 0) << r.err;
  j = nlohmann::json::parse(slurp(json));
  EXPECT_EQ(j["pairs"], 5);  // (0,2) (2,4) ... (8,10)
  EXPECT_LT(j["translation_m"]["max"].get<double>(), 1e-12);
}

}  // namespace
