#pragma once
// What a command may write (README, "Outputs"): only where an --out/--json style option says, an
// existing output only with --force, and never into its input. Checked before any work starts;
// the write itself is atomic (core/atomic_file.hpp, eval::publishDirectoryAtomically), so a
// failed --force run leaves the old bytes in place.

#include <filesystem>
#include <string>

#include "eval/formats/dataset_io.hpp"

namespace slamprep::app {

/// An output file: refused (InputError naming `option` and the path) when it exists and `force`
/// is false, or when it is a directory.
void checkOutputFile(const std::filesystem::path& file, const std::string& option, bool force);

/// An output dataset directory: refused when it exists and `force` is false, and even with
/// `force` when it is not a directory that holds a dataset.json or nothing (a typo such as
/// `--out ~` must never replace a home folder).
void checkOutputDataset(const std::filesystem::path& dir, const std::string& option, bool force);

/// The same for another kind of output directory: `replaceable` says which existing ones --force
/// may replace, `kind` names them in the message ("a trajectories folder (only *.tum, *.txt)").
void checkOutputDirectory(const std::filesystem::path& dir, const std::string& option, bool force,
                          const eval::ReplaceableDirectory& replaceable, const std::string& kind);

/// An input that must exist: a dataset directory (with dataset.json) or a readable file.
void checkInputDataset(const std::filesystem::path& dir, const std::string& option);
void checkInputFile(const std::filesystem::path& file, const std::string& option);

/// Refused when `out` is `input` or lies inside it: a command never writes into its input.
void checkNotInside(const std::filesystem::path& out, const std::filesystem::path& input,
                    const std::string& option);

}  // namespace slamprep::app
