#pragma once
// One word of a POSIX shell command line, whatever it holds: the Slurm scripts bench writes
// (eval/bench/slurm.cpp) and the tests that run slamprep through std::system
// (tests/support/cli_run.hpp). Header-only, so that a test linking no library can use it.

#include <string>
#include <string_view>

namespace slamprep {

/// `word` inside single quotes, each ' in it written '\'' (single quotes protect every other
/// character: spaces, $, `, ;, \, newlines).
inline std::string shellQuote(std::string_view word) {
  std::string quoted = "'";
  for (const char c : word) {
    if (c == '\'')
      quoted += "'\\''";  // close the quotes, an escaped quote, open them again
    else
      quoted += c;
  }
  quoted += '\'';
  return quoted;
}

}  // namespace slamprep
