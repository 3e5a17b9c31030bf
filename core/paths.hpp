#pragma once
// Locating the project's data files (worlds, scenarios, suites) from any working directory, for
// the binary in its build tree and for an installed (and possibly moved) prefix alike.

#include <filesystem>

namespace slamprep {

/// The folder holding worlds/ and eval/suites/, first that applies:
///   1. $SLAMPREP_DATA_DIR when set and not empty (taken as given);
///   2. <exe_dir>/../share/slamprep, an installed prefix (wherever it was moved to);
///   3. <exe_dir>/share/slamprep, the build tree (symlinks into the sources, made by CMake).
/// <exe_dir> is the folder of /proc/self/exe. Empty when none of them exists.
std::filesystem::path dataDir();

/// A data path as given if it is absolute or exists relative to the working directory, otherwise
/// the same relative path under dataDir() if that exists; otherwise unchanged (the reader then
/// reports the path as the user wrote it).
std::filesystem::path resolveDataPath(const std::filesystem::path& path);

/// `path` absolute, with its symlinks and `..` resolved as far as it exists and no trailing
/// slash: the form in which the output guard compares paths ("ds/", "./ds" and a link to ds are
/// one folder).
std::filesystem::path resolvedPath(const std::filesystem::path& path);

/// Whether resolvedPath(inner) is resolvedPath(outer) or lies below it.
bool isSameOrInside(const std::filesystem::path& inner, const std::filesystem::path& outer);

}  // namespace slamprep
