#pragma once
// The flags several commands share, declared once so that they keep one name, one default and
// one meaning everywhere (README, "Outputs" and "Exit codes"): --force, --strict, -q/--quiet and
// --json FILE. A command says only what they cover for it: what --force replaces, when --strict
// exits 3, what --json writes.

#include <CLI/CLI.hpp>
#include <string>

namespace slamprep::app {

/// A command's flags struct derives from this; a command adds only the flags it has.
struct CommonFlags {
  bool force = false;    ///< --force: replace an existing output slamprep may replace (OutputGuard)
  bool strict = false;   ///< --strict: any refusal exits 3, not only all (refusalExitCode)
  bool quiet = false;    ///< -q,--quiet: no progress output (CommandProgress)
  std::string json_out;  ///< --json FILE: the machine-readable result; empty: not written
};

/// --force; `replaces` names the command's outputs: "an existing --out dataset".
CLI::Option* addForce(CLI::App* cli, CommonFlags& flags, const std::string& replaces);

/// --strict; `when` says which partial failure then exits 3: "when any scan fell back".
CLI::Option* addStrict(CLI::App* cli, CommonFlags& flags, const std::string& when);

/// -q,--quiet.
CLI::Option* addQuiet(CLI::App* cli, CommonFlags& flags);

/// --json FILE, checked as an output path; `writes` says what goes in it: "the summary".
CLI::Option* addJson(CLI::App* cli, CommonFlags& flags, const std::string& writes);

}  // namespace slamprep::app
