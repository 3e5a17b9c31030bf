#pragma once
// Partial outputs (`<name>.partial-<pid>`, the files and folders a write fills before renaming
// them into place) removed when SIGINT, SIGTERM or SIGHUP ends the process, so an interrupted run
// leaves neither a half-written output nor a large partial beside the old one.

#include <filesystem>

namespace slamprep {

/// Installs the handler for SIGINT, SIGTERM and SIGHUP (not for a signal the process was started
/// with ignored, e.g. a `nohup` run's SIGHUP): it removes every partial in flight, then re-raises
/// the signal with its default action, so the exit status still says which signal ended it.
/// Call once, early in main().
void removePartialsOnSignal();

/// Registers `path` (a file or a folder, made absolute here) for removal by that handler while
/// this object lives: construct it before the partial is created, destroy it once the partial
/// was renamed into place or removed. Best effort: beyond 16 at once (or a path longer than
/// PATH_MAX), a partial is not registered.
class PartialInFlight {
 public:
  explicit PartialInFlight(const std::filesystem::path& path);
  ~PartialInFlight();
  PartialInFlight(const PartialInFlight&) = delete;
  PartialInFlight& operator=(const PartialInFlight&) = delete;

 private:
  int slot_ = -1;
};

}  // namespace slamprep
