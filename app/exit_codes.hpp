#pragma once
// The exit codes of every slamprep command (README, "Exit codes").

namespace slamprep::app {

inline constexpr int kExitDone = 0;      ///< the requested work is done
inline constexpr int kExitInternal = 1;  ///< internal error: a bug, not the user's input
inline constexpr int kExitUsage = 2;     ///< bad input or usage (files, flags, data), named
inline constexpr int kExitNotDone = 3;   ///< the requested work could not be done (refusals)

/// kExitNotDone when nothing requested succeeded (every method refused), or with --strict when
/// anything was refused; else kExitDone. Methods that do not apply to the data are not requested.
inline int refusalExitCode(bool nothing_succeeded, bool any_refused, bool strict) {
  return nothing_succeeded || (strict && any_refused) ? kExitNotDone : kExitDone;
}

}  // namespace slamprep::app
