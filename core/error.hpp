#pragma once
// User-facing input errors: always name the file, and the line or field where known.

#include <stdexcept>
#include <string>

namespace slamprep {

/// Bad input from a user (file, flag, degenerate data). The CLI prints what() and exits non-zero.
class InputError : public std::runtime_error {
 public:
  /// `where` is "file", "file:line" or "file: field"; `what` says what is wrong.
  InputError(const std::string& where, const std::string& what)
      : std::runtime_error(where.empty() ? what : where + ": " + what) {}
};

}  // namespace slamprep
