#pragma once
// Locating the project's data files (worlds, scenarios, suites) from any working directory.

#include <filesystem>
#include <string>

namespace slamprep {

/// The source tree slamprep was built from (world files, suites live there).
std::filesystem::path sourceDir();

/// A data path as given if it exists relative to the working directory, otherwise the same
/// relative path under sourceDir() if that exists; otherwise unchanged (the reader reports it).
std::filesystem::path resolveDataPath(const std::filesystem::path& path);

}  // namespace slamprep
