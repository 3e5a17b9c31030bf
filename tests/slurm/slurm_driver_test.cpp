// The parts of the Slurm driver that need no Slurm: scontrol parsing, quoting, the job scripts
// and which shards a resubmission must run. The real-Slurm test is slurm_bench_test.sh.
#include <gtest/gtest.h>

#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <sstream>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/shell_quote.hpp"
#include "slamprep/eval/bench/bench.hpp"
#include "slamprep/eval/bench/runner.hpp"
#include "slamprep/eval/bench/slurm.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

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

// The argument of one "#SBATCH --opt=ARG" line as sbatch (22.05, src/sbatch/opt.c) reads it: a
// blank outside quotes ends it even after a backslash, a backslash takes the next character as
// it is, quotes group, an unquoted '#' starts a comment.
std::string sbatchArgument(const std::string& line) {
  std::string out;
  bool escaped = false;
  char quote = 0;
  for (char c : line.substr(line.find('=') + 1)) {
    if (!quote && std::isspace(static_cast<unsigned char>(c))) break;
    if (escaped) {
      escaped = false;
    } else if (c == '\\') {
      escaped = true;
      continue;
    } else if (quote) {
      if (c == quote) {
        quote = 0;
        continue;
      }
    } else if (c == '"' || c == '\'') {
      quote = c;
      continue;
    } else if (c == '#') {
      break;
    }
    out += c;
  }
  return out;
}

std::string lineStartingWith(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(prefix, 0) == 0) return line;
  return "";
}

// A suite named "x'\ntouch pwned\n#" landed unquoted in the comments and
// #SBATCH lines, and the shard script ran `touch pwned`. Control characters are refused now.
TEST(SlurmDriver, NamesWithANewlineAreRefused) {
  const test::ScratchDir scratch("slurm_newline");
  SlurmParams params;
  params.suite_arg = "regression";
  params.results_root = scratch.path();
  const fs::path out_dir = scratch / "x'\ntouch pwned\n#";
  try {
    writeSlurmScripts(params, out_dir);
    FAIL() << "wrote scripts for a name with a newline";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("suite name 'x'\\x0atouch pwned\\x0a#'"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("control character"), std::string::npos);
  }
  EXPECT_FALSE(fs::exists(out_dir));
  params.results_root = scratch / "tab\there";
  EXPECT_THROW(writeSlurmScripts(params, params.results_root / "ok"), InputError);
}

// Every other character stays inside its word: bash parses the script (bash -n), a dry run runs
// nothing the names hold, and sbatch's directive parser reads the job name and log path whole.
TEST(SlurmDriver, OddNamesStayOneWordForBashAndSbatch) {
  const test::ScratchDir scratch("slurm_odd");
  const std::string name = "odd name #1 $(touch pwned) `touch pwned` 'q' \"d\" 50% \\";
  SlurmParams params;
  params.shards = 3;
  params.jobs = 1;
  params.results_root = scratch / "results dir";
  params.suite_arg = (scratch / "suites; touch pwned" / "s.yaml").string();
  const fs::path out_dir = params.results_root / name;
  const auto scripts = writeSlurmScripts(params, out_dir);
  const std::string shard = readFile(scripts.shard_script);
  EXPECT_EQ(lineStartingWith(shard, "touch pwned"), "");
  EXPECT_EQ(std::system(("bash -n " + shellQuote(scripts.shard_script.string()) + " && bash -n " +
                         shellQuote(scripts.merge_script.string()))
                            .c_str()),
            0);

  // A dry run: `exec` replaced by a function that writes its arguments, one per line.
  const fs::path args = scratch / "args.txt";
  const std::string dry =
      "cd " + shellQuote(scratch.path().string()) + " && SLURM_ARRAY_TASK_ID=2 bash -c " +
      shellQuote("exec() { printf '%s\\n' \"$@\" > " + shellQuote(args.string()) + "; }; source " +
                 shellQuote(scripts.shard_script.string()));
  ASSERT_EQ(std::system(dry.c_str()), 0) << dry;
  std::string expected;
  for (const std::string& a :
       {fs::read_symlink("/proc/self/exe").string(), std::string("bench"), std::string("--quiet"),
        std::string("--no-plots"), std::string("--suite"), params.suite_arg,
        std::string("--results"), params.results_root.string(), std::string("--shard"),
        std::string("2/3"), std::string("--jobs"), std::string("1")})
    expected += a + "\n";
  EXPECT_EQ(readFile(args).substr(readFile(args).find('\n') + 1),
            expected.substr(expected.find('\n') + 1));  // the binary path: exec's first word
  for (const auto& entry : fs::recursive_directory_iterator(scratch.path()))
    EXPECT_NE(entry.path().filename(), "pwned") << entry.path();
  EXPECT_FALSE(fs::exists(fs::current_path() / "pwned"));

  EXPECT_EQ(sbatchArgument(lineStartingWith(shard, "#SBATCH --job-name=")), "slamprep-" + name);
  // In --output, "%%" is Slurm's literal '%' and %a the array task.
  std::string log = (out_dir / "slurm").string() + "/shard-%a-of-3.log";
  std::string escaped_log;
  for (std::size_t i = 0; i < log.size(); ++i)
    escaped_log +=
        log[i] == '%' && log.compare(i, 2, "%a") != 0 ? std::string("%%") : std::string(1, log[i]);
  EXPECT_EQ(sbatchArgument(lineStartingWith(shard, "#SBATCH --output=")), escaped_log);
  const std::string merge = readFile(scripts.merge_script);
  EXPECT_EQ(sbatchArgument(lineStartingWith(merge, "#SBATCH --job-name=")),
            "slamprep-" + name + "-merge");
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

// A shard whose results this build made from the same inputs is not resubmitted: the stored
// specs carry the world and scenario digests, which the check must take as bench stores them.
TEST(SlurmDriver, ACompleteShardIsNotResubmitted) {
  Suite suite;
  suite.name = "slurm-complete";
  suite.worlds = {"worlds/room.yaml"};
  suite.scenarios = {"worlds/scenarios/arc.yaml"};
  suite.seeds = 4;
  const test::ScratchDir scratch("slurm_complete");
  const fs::path dir = scratch / "results" / suite.name;
  auto trials = expandTrials(suite);
  attachInputDigests(trials);
  const Shard first{1, 2};
  const fs::path shard_dir = dir / "shards" / first.name();
  writeFileAtomic(shard_dir / ".slamprep-build", binaryFingerprint());
  for (const auto& t : trials)
    if (first.contains(t.index))
      writeFileAtomic(shard_dir / "trials" / (t.id + ".json"),
                      nlohmann::json{{"trial", specJson(t)}}.dump());
  EXPECT_EQ(incompleteShards(suite, dir, 2), (std::vector<int>{2}));
}

}  // namespace
}  // namespace slamprep::eval
