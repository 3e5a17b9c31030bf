#include "slamprep/core/paths.hpp"

#include <gtest/gtest.h>

#include <cstdlib>
#include <fstream>
#include <optional>
#include <string>

#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep {
namespace {

namespace fs = std::filesystem;

// A temporary data folder holding worlds/room.yaml, with SLAMPREP_DATA_DIR pointing at it for
// the test's lifetime (ctest sets the variable to the build tree's data folder: restored after).
class DataDirTest : public ::testing::Test {
 protected:
  void SetUp() override {
    if (const char* env = std::getenv("SLAMPREP_DATA_DIR")) saved_ = env;
    fs::create_directories(root_ / "data" / "worlds");
    std::ofstream(root_ / "data" / "worlds" / "room.yaml") << "name: room\n";
    ::setenv("SLAMPREP_DATA_DIR", (root_ / "data").c_str(), 1);
  }
  void TearDown() override {
    if (saved_)
      ::setenv("SLAMPREP_DATA_DIR", saved_->c_str(), 1);
    else
      ::unsetenv("SLAMPREP_DATA_DIR");
  }
  const test::ScratchDir scratch_{"paths"};
  const fs::path root_ = scratch_.path();
  std::optional<std::string> saved_;
};

TEST_F(DataDirTest, EnvironmentVariableNamesTheDataDir) {
  EXPECT_EQ(dataDir(), root_ / "data");
}

TEST_F(DataDirTest, RelativePathResolvesUnderTheDataDir) {
  EXPECT_EQ(resolveDataPath("worlds/room.yaml"), root_ / "data" / "worlds" / "room.yaml");
}

TEST_F(DataDirTest, WorkingDirectoryWinsOverTheDataDir) {
  fs::create_directories(root_ / "cwd" / "worlds");
  std::ofstream(root_ / "cwd" / "worlds" / "room.yaml") << "name: mine\n";
  const fs::path before = fs::current_path();
  fs::current_path(root_ / "cwd");
  const fs::path resolved = resolveDataPath("worlds/room.yaml");
  fs::current_path(before);
  EXPECT_EQ(resolved, fs::path("worlds/room.yaml"));
}

TEST_F(DataDirTest, MissingAndAbsolutePathsStayAsGiven) {
  EXPECT_EQ(resolveDataPath("worlds/absent.yaml"), fs::path("worlds/absent.yaml"));
  EXPECT_EQ(resolveDataPath("/no/such/room.yaml"), fs::path("/no/such/room.yaml"));
}

// Unset, the executable decides: this test binary sits in <build>/tests/core/, with no data
// folder beside it (share/slamprep) nor in ../share/slamprep, so nothing resolves.
TEST_F(DataDirTest, WithoutTheVariableTheExecutableDecides) {
  ::unsetenv("SLAMPREP_DATA_DIR");
  EXPECT_EQ(dataDir(), fs::path());
  EXPECT_EQ(resolveDataPath("worlds/room.yaml"), fs::path("worlds/room.yaml"));
}

}  // namespace
}  // namespace slamprep
