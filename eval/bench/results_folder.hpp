#pragma once
// A results folder (results/<suite>/) is bench's own: bench creates it with a marker file, and
// bench, merge and plot write (and resume, --fresh: delete trials/ and timing/) only in a folder
// that holds the marker. A folder they did not create is refused, never cleaned (docs/results.md).

#include <filesystem>
#include <string>

namespace slamprep::eval {

/// The marker's file name, and its text (the same bytes in every results folder).
inline constexpr const char* kResultsMarker = ".slamprep-results";
std::string resultsMarkerText();

/// For bench: creates `dir` with the marker when nothing is there (atomically: the folder never
/// exists without it, so concurrent shards agree), else requires the marker. InputError naming
/// `option` (e.g. "--results out") and `dir` otherwise.
void claimResultsFolder(const std::filesystem::path& dir, const std::string& option);

/// For merge and plot: `dir` must be a folder holding the marker.
void requireResultsFolder(const std::filesystem::path& dir, const std::string& option);

}  // namespace slamprep::eval
