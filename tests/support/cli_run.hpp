#pragma once
// Runs the slamprep binary this build made, as a user would, for the tests that check a command
// end to end: its exit code and what it printed. Each argument reaches the command as one word
// whatever it holds (spaces, quotes, $, ;), so a test's path can neither split nor run anything.

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "slamprep/core/shell_quote.hpp"

namespace slamprep::test {

/// What one run returned and printed.
struct CliRun {
  int exit_code = -1;  ///< -1 when the command did not exit by itself (a signal)
  std::string out;     ///< stdout
  std::string err;     ///< stderr
};

/// The whole of `file`; empty when it cannot be read.
inline std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Runs `slamprep ARGS...`; stdout and stderr pass through `scratch`/stdout and `scratch`/stderr
/// (the caller's own folder, overwritten by every run).
inline CliRun runSlamprep(const std::vector<std::string>& args,
                          const std::filesystem::path& scratch) {
  // Appended piecewise: GCC 12 warns falsely (-Wrestrict) on "literal" + std::string.
  std::string command =
      shellQuote((std::filesystem::path(SLAMPREP_BINARY_DIR) / "slamprep").string());
  for (const std::string& arg : args) command.append(" ").append(shellQuote(arg));
  command.append(" >").append(shellQuote((scratch / "stdout").string()));
  command.append(" 2>").append(shellQuote((scratch / "stderr").string()));
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, slurp(scratch / "stdout"),
          slurp(scratch / "stderr")};
}

}  // namespace slamprep::test
