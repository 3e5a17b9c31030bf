#include "slamprep/eval/bench/results_folder.hpp"

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/partial_cleanup.hpp"

namespace slamprep::eval {
namespace fs = std::filesystem;

std::string resultsMarkerText() {
  return "slamprep results folder: `slamprep bench` created it; bench, merge and plot write here "
         "and may replace what they wrote (docs/results.md).\n";
}

void requireResultsFolder(const fs::path& dir, const std::string& option) {
  std::error_code ec;
  if (!fs::is_directory(dir, ec))
    throw InputError(option + " " + dir.string(), "no such results folder");
  if (!fs::is_regular_file(dir / kResultsMarker, ec))
    throw InputError(option + " " + dir.string(),
                     std::string("exists but has no ") + kResultsMarker +
                         ": not a results folder slamprep bench created, so nothing in it is "
                         "written or deleted. Choose another folder; if it is one an older "
                         "slamprep wrote, add the marker: touch " +
                         (dir / kResultsMarker).string());
}

void claimResultsFolder(const fs::path& dir, const std::string& option) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(dir, ec))) {
    if (dir.has_parent_path()) fs::create_directories(dir.parent_path(), ec);
    const fs::path partial = partialSibling(dir);
    const PartialInFlight in_flight(partial);
    fs::remove_all(partial, ec);
    try {
      if (!fs::create_directory(partial, ec))
        throw InputError(option + " " + dir.string(), "cannot create: " + ec.message());
      writeFileAtomic(partial / kResultsMarker, resultsMarkerText());
      renameIfAbsent(partial, dir);  // false: another shard made it first, with its marker
    } catch (...) {
      fs::remove_all(partial, ec);
      throw;
    }
    fs::remove_all(partial, ec);
  }
  requireResultsFolder(dir, option);
}

}  // namespace slamprep::eval
