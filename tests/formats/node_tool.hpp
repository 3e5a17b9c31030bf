#pragma once
// Runs tests/formats/mcap_reader/mcap_tool.mjs (the independent @mcap/core reader and writer).
// When node or the npm packages are missing, nodeToolUnavailable() says why, and the test skips,
// except under CI=true, where a missing tool fails the test: CI must not pass by skipping.

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "slamprep/tests/support/scratch_dir.hpp"

namespace slamprep::test {

inline std::filesystem::path nodeToolDir() {
  return std::filesystem::path(SLAMPREP_SOURCE_DIR) / "tests" / "formats" / "mcap_reader";
}

inline int runShell(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Empty when the tool can run; otherwise the reason. Installs the locked npm packages with
/// `npm ci` once (under a lock on the tool's folder, as ctest runs tests in parallel) when they
/// are missing. Locking the folder itself leaves no lock file behind.
inline std::string nodeToolUnavailable() {
  const auto dir = nodeToolDir();
  if (runShell("node --version > /dev/null 2>&1") != 0) return "node is not installed";
  if (!std::filesystem::exists(dir / "node_modules" / "@mcap" / "core")) {
    const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY);
    if (fd >= 0) ::flock(fd, LOCK_EX);
    if (!std::filesystem::exists(dir / "node_modules" / "@mcap" / "core"))
      runShell("cd '" + dir.string() +
               "' && npm ci --no-audit --no-fund --loglevel=error > /dev/null 2>&1");
    if (fd >= 0) ::close(fd);
  }
  if (!std::filesystem::exists(dir / "node_modules" / "@mcap" / "core"))
    return "npm packages missing and `npm ci` in " + dir.string() +
           " failed (no npm or no registry): run scripts/install-deps.sh";
  return {};
}

/// True when the environment says this is CI (CI=true, as GitHub and GitLab set it).
inline bool runningInCi() {
  const char* ci = std::getenv("CI");
  return ci != nullptr && std::string(ci) == "true";
}

/// Runs `node mcap_tool.mjs args`; returns its exit code, stderr in `log`.
inline int runNodeTool(const std::string& args, std::string* log = nullptr) {
  const ScratchDir scratch("mcap_tool");
  const auto err = scratch / "stderr";
  const int rc = runShell("node '" + (nodeToolDir() / "mcap_tool.mjs").string() + "' " + args +
                          " 2> '" + err.string() + "'");
  if (log) {
    std::ifstream in(err);
    std::stringstream s;
    s << in.rdbuf();
    *log = s.str();
  }
  return rc;
}

}  // namespace slamprep::test

/// Skips the test when the independent MCAP reader cannot run; fails it instead under CI=true.
#define SLAMPREP_REQUIRE_NODE_TOOL()                                                     \
  do {                                                                                   \
    if (const std::string why = ::slamprep::test::nodeToolUnavailable(); !why.empty()) { \
      if (::slamprep::test::runningInCi()) FAIL() << why << " (CI=true: no skips)";      \
      GTEST_SKIP() << why;                                                               \
    }                                                                                    \
  } while (false)
