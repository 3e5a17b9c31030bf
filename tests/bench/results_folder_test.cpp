// bench owns only what it wrote: a results folder it created holds the marker, a folder without
// it is refused and left alone, and a suite's name is one folder name (never a path).
#include "slamprep/eval/bench/results_folder.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/bench/suite.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::eval {
namespace {

namespace fs = std::filesystem;

std::string refusal(const std::function<void()>& call) {
  try {
    call();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ResultsFolder, BenchCreatesItWithTheMarkerAndComesBack) {
  const test::ScratchDir scratch("results_claim");
  const fs::path dir = scratch / "root" / "tiny";
  claimResultsFolder(dir, "--results");
  EXPECT_EQ(readFile(dir / kResultsMarker), resultsMarkerText());
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.parent_path()), fs::directory_iterator()), 1)
      << "a partial sibling was left beside the new folder";
  std::ofstream(dir / "summary.json") << "{}";
  claimResultsFolder(dir, "--results");  // a rerun resumes in its own folder
  requireResultsFolder(dir, "RESULTS_DIR");
  EXPECT_EQ(readFile(dir / "summary.json"), "{}");
}

TEST(ResultsFolder, AFolderBenchDidNotCreateIsRefusedAndLeftAlone) {
  const test::ScratchDir scratch("results_foreign");
  const fs::path dir = scratch / "tiny";
  fs::create_directories(dir / "trials");
  std::ofstream(dir / "trials" / "mine.csv") << "mine\n";
  const std::string why = refusal([&] { claimResultsFolder(dir, "--results"); });
  EXPECT_NE(why.find("--results " + dir.string() + ": exists but has no .slamprep-results"),
            std::string::npos)
      << why;
  EXPECT_NE(refusal([&] { requireResultsFolder(dir, "RESULTS_DIR"); }).find("RESULTS_DIR"),
            std::string::npos);
  EXPECT_EQ(readFile(dir / "trials" / "mine.csv"), "mine\n");
  EXPECT_FALSE(fs::exists(dir / kResultsMarker));
  std::ofstream(scratch / "file") << "x";
  EXPECT_NE(refusal([&] { claimResultsFolder(scratch / "file", "--results"); }), "");
  EXPECT_NE(refusal([&] { requireResultsFolder(scratch / "absent", "RESULTS_DIR"); }), "");
}

std::string suiteNameRefusal(const std::string& name_line) {
  static const test::ScratchDir scratch("suite_names");
  const fs::path file = scratch / "s.yaml";
  std::ofstream(file) << "worlds: [worlds/room.yaml]\nscenarios: [worlds/scenarios/arc.yaml]\n"
                      << name_line << "\n";
  return refusal([&] { loadSuite(file); });
}

TEST(SuiteName, IsOneFileNamePart) {
  for (const std::string line :
       {"name: ../../victim", "name: /tmp/victim", "name: a/b", "name: \"\"", "name: .", "name: ..",
        "name: \"x'\\ntouch pwned\\n#\"", "name: \"tab\\there\""}) {
    const std::string why = suiteNameRefusal(line);
    EXPECT_NE(why.find("s.yaml:3:7: name: "), std::string::npos) << line << " -> " << why;
  }
  EXPECT_EQ(suiteNameRefusal("name: sweep-speed_2.v1"), "");
}

TEST(SuiteName, AFileStemThatIsNoFolderNameIsRefusedToo) {
  const test::ScratchDir scratch("suite_stem");
  const fs::path file = scratch / "..yaml";  // stem "."
  std::ofstream(file) << "worlds: [a]\nscenarios: [b]\n";
  EXPECT_NE(refusal([&] { loadSuite(file); }).find(": name: "), std::string::npos);
}

}  // namespace
}  // namespace slamprep::eval
