// The pieces of the output guard that live in core: resolved path relations, the partial sibling's
// name, an output that must not be replaced at the final rename, and partials removed on a signal.
#include "slamprep/core/atomic_file.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <csignal>
#include <fstream>
#include <string>

#include "slamprep/core/error.hpp"
#include "slamprep/core/partial_cleanup.hpp"
#include "slamprep/core/paths.hpp"
#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep {
namespace {

namespace fs = std::filesystem;

TEST(ResolvedPath, SlashesDotsAndLinksNameOneFolder) {
  const test::ScratchDir scratch("resolved");
  fs::create_directories(scratch / "data" / "ds");
  fs::create_directory_symlink(scratch / "data", scratch / "link");
  const fs::path ds = resolvedPath(scratch / "data" / "ds");
  EXPECT_EQ(resolvedPath(scratch / "data" / "ds" / ""), ds);
  EXPECT_EQ(resolvedPath(scratch / "data" / "x" / ".." / "ds"), ds);
  EXPECT_EQ(resolvedPath(scratch / "link" / "ds"), ds);
  EXPECT_TRUE(isSameOrInside(scratch / "link" / "ds" / "new.json", scratch / "data" / "ds"));
  EXPECT_TRUE(isSameOrInside(scratch / "data", scratch / "link"));
  // A sibling whose name starts the same is not inside.
  EXPECT_FALSE(isSameOrInside(scratch / "data" / "ds2", scratch / "data" / "ds"));
  EXPECT_FALSE(isSameOrInside(scratch / "data", scratch / "data" / "ds"));
}

TEST(PartialSibling, FitsTheNameLimitWhenTheTargetDoes) {
  const std::string pid = std::to_string(::getpid());
  EXPECT_EQ(partialSibling("out/ds/"), fs::path("out/ds.partial-" + pid));
  EXPECT_EQ(partialSibling("out/ds", "old"), fs::path("out/ds.old-" + pid));
  const std::string longest(255, 'a');  // a legal name: its sibling must be one too
  const fs::path sibling = partialSibling(fs::path("out") / longest);
  EXPECT_EQ(sibling.filename().string().size(), 255u);
  EXPECT_EQ(sibling.filename().string().substr(255 - pid.size() - 9), ".partial-" + pid);
}

TEST(AtomicFile, ALongLegalNameIsWritten) {
  const test::ScratchDir scratch("long_name");
  const fs::path file = scratch / std::string(250, 'n');
  writeFileAtomic(file, "x\n");  // was ENAMETOOLONG: "<name>.partial-<pid>" is 264 bytes
  EXPECT_EQ(readFile(file), "x\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(scratch.path()), fs::directory_iterator()), 1);
}

// An output given without --force: created when absent, never replaced when it appeared.
TEST(AtomicFile, AProtectedOutputIsCreatedButNeverReplaced) {
  const test::ScratchDir scratch("protected");
  const fs::path file = scratch / "out.json";
  refuseToReplace(scratch / "." / "out.json", "--json");  // the same file, spelt differently
  EXPECT_FALSE(mayReplace(file));
  writeFileAtomic(file, "first\n");
  try {
    writeFileAtomic(file, "second\n");
    FAIL() << "replaced an output given without --force";
  } catch (const InputError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("--json " + file.string() + ": appeared while this command ran"),
              std::string::npos)
        << what;
  }
  EXPECT_EQ(readFile(file), "first\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(scratch.path()), fs::directory_iterator()), 1)
      << "the discarded output's partial file was left";
  EXPECT_TRUE(mayReplace(scratch / "other.json"));
}

TEST(AtomicFile, AProtectedFolderIsNotReplacedByRenameEither) {
  const test::ScratchDir scratch("protected_dir");
  fs::create_directories(scratch / "new");
  fs::create_directories(scratch / "ds");  // appeared meanwhile (empty: rename(2) would replace)
  refuseToReplace(scratch / "ds", "--out");
  EXPECT_THROW(renameIntoPlace(scratch / "new", scratch / "ds"), InputError);
  EXPECT_TRUE(fs::is_directory(scratch / "new"));
  EXPECT_FALSE(renameIfAbsent(scratch / "new", scratch / "ds"));
  fs::remove(scratch / "ds");
  EXPECT_TRUE(renameIfAbsent(scratch / "new", scratch / "ds"));
  EXPECT_FALSE(fs::exists(scratch / "new"));
}

// Fills a partial folder (300 files and a subfolder) and a partial file, then is killed.
void killedWhileWriting(const fs::path& partial, const fs::path& file, const fs::path& kept) {
  removePartialsOnSignal();
  const PartialInFlight folder(partial);
  const PartialInFlight single(file);
  fs::create_directories(partial / "spill");
  for (int i = 0; i < 300; ++i) std::ofstream(partial / std::to_string(i)) << i;
  std::ofstream(partial / "spill" / "scans.bin") << "ranges";
  std::ofstream(file) << "{}";
  std::ofstream(kept) << "not a partial";
  std::raise(SIGTERM);
}

// SIGTERM in the middle of a write: the process still dies of the signal, and the partials are
// gone; what was not registered stays.
TEST(PartialCleanup, ASignalRemovesThePartialsInFlight) {
  const test::ScratchDir scratch("signal");
  const fs::path partial = scratch / "ds.partial-1";
  const fs::path file = scratch / "out.json.partial-1";
  EXPECT_EXIT(killedWhileWriting(partial, file, scratch / "kept"),
              ::testing::KilledBySignal(SIGTERM), "");
  EXPECT_FALSE(fs::exists(partial));
  EXPECT_FALSE(fs::exists(file));
  EXPECT_TRUE(fs::exists(scratch / "kept"));
}

TEST(PartialCleanup, AFinishedWriteIsNoLongerRegistered) {
  const test::ScratchDir scratch("signal_done");
  const fs::path kept = scratch / "ds";
  EXPECT_EXIT(
      {
        removePartialsOnSignal();
        { const PartialInFlight done(kept); }  // renamed into place: no longer a partial
        fs::create_directories(kept);
        std::raise(SIGINT);
      },
      ::testing::KilledBySignal(SIGINT), "");
  EXPECT_TRUE(fs::is_directory(kept));
}

}  // namespace
}  // namespace slamprep
