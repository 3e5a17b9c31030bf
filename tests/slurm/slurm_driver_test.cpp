// The parts of the Slurm driver that need no Slurm: scontrol parsing, quoting, the job scripts
// and which shards a resubmission must run. The real-Slurm test is slurm_bench_test.sh.
#include <gtest/gtest.h>

#include <filesystem>

#include "core/atomic_file.hpp"
#include "eval/bench/slurm.hpp"
#include "tests/support/scratch_dir.hpp"

namespace slamprep::eval {
namespace {

namespace fs = std::filesystem;

// Trimmed from Slurm 22.05 `scontrol show job` of a 3-task array, one task failed, one pending.
constexpr const char* kArray =
    "JobId=7 ArrayJobId=5 ArrayTaskId=3 JobName=slamprep-x\n"
    "   UserId=root(0) GroupId=root(0)\n"
    "   JobState=COMPLETED Reason=None Dependency=(null)\n"
    "\n"
    "JobId=6 ArrayJobId=5 ArrayTaskId=2 JobName=slamprep-x\n"
    "   JobState=FAILED Reason=NonZeroExitCode Dependency=(null)\n"
    "\n"
    "JobId=5 ArrayJobId=5 ArrayTaskId=4-5 JobName=slamprep-x\n"
    "   JobState=PENDING Reason=None Dependency=(null)\n";

TEST(SlurmDriver, ParsesEveryArrayRecord) {
  const auto records = parseScontrolJobs(kArray);
  ASSERT_EQ(records.size(), 3u);
  EXPECT_EQ(records[0].array_task_id, "3");
  EXPECT_EQ(records[0].state, "COMPLETED");
  EXPECT_EQ(records[1].array_task_id, "2");
  EXPECT_EQ(records[1].state, "FAILED");
  EXPECT_EQ(records[2].array_task_id, "4-5");
  EXPECT_EQ(records[2].state, "PENDING");
}

TEST(SlurmDriver, ParsesPlainJob) {
  const auto records = parseScontrolJobs(
      "JobId=9 JobName=merge\n   JobState=CANCELLED Reason=DependencyNeverSatisfied "
      "Dependency=afterok:5_*(failed)\n");
  ASSERT_EQ(records.size(), 1u);
  EXPECT_EQ(records[0].array_task_id, "");
  EXPECT_EQ(records[0].state, "CANCELLED");
}

TEST(SlurmDriver, QuotesForBash) {
  EXPECT_EQ(shellQuote("/a b/c"), "'/a b/c'");
  EXPECT_EQ(shellQuote("it's"), "'it'\\''s'");
  EXPECT_EQ(shellQuote("$HOME;rm"), "'$HOME;rm'");
}

TEST(SlurmDriver, ScriptsAreBashWithAbsolutePaths) {
  const test::ScratchDir scratch("slurm_driver");
  const fs::path dir = scratch / "results";
  SlurmParams params;
  params.shards = 3;
  params.suite_arg = "regression";
  params.results_root = dir;
  const auto scripts = writeSlurmScripts(params, dir / "regression");
  const std::string shard = readFile(scripts.shard_script);
  const std::string merge = readFile(scripts.merge_script);
  EXPECT_EQ(shard.rfind("#!/bin/bash\n", 0), 0u);
  EXPECT_EQ(merge.rfind("#!/bin/bash\n", 0), 0u);
  EXPECT_NE(shard.find("set -euo pipefail"), std::string::npos);
  EXPECT_NE(shard.find("--shard \"${SLURM_ARRAY_TASK_ID}/3\""), std::string::npos);
  EXPECT_NE(shard.find("--results " + shellQuote(dir.string())), std::string::npos);
  EXPECT_NE(merge.find(" merge " + shellQuote((dir / "regression").string())), std::string::npos);
  EXPECT_NE(shard.find("exec '/"), std::string::npos);  // absolute binary path
}

TEST(SlurmDriver, EmptyResultsNeedEveryShard) {
  Suite suite;
  suite.name = "slurm-missing";
  suite.worlds = {"worlds/room.yaml"};
  suite.scenarios = {"worlds/scenarios/arc.yaml"};
  suite.seeds = 5;
  const test::ScratchDir scratch("slurm_missing");
  const fs::path dir = scratch / "results";  // never written: no shard has run
  EXPECT_EQ(incompleteShards(suite, dir, 3), (std::vector<int>{1, 2, 3}));
}

}  // namespace
}  // namespace slamprep::eval
