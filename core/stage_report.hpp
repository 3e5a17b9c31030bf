#pragma once
// Stage reports of the task running in this process (a bench trial, a command) to whoever shows
// progress: the bench runner's parent process through a pipe, or a command's own Progress.
// Process-wide because every trial runs in its own forked process. Reports never touch results.

#include <functional>
#include <string>

#include "slamprep/core/progress.hpp"

namespace slamprep {

using StageSink = std::function<void(const StageEvent&)>;

/// Sends this process's stage reports to `sink` while alive (none by default: reports vanish).
class ScopedStageSink {
 public:
  explicit ScopedStageSink(StageSink sink);
  ~ScopedStageSink();
  ScopedStageSink(const ScopedStageSink&) = delete;
  ScopedStageSink& operator=(const ScopedStageSink&) = delete;

 private:
  StageSink previous_;
};

/// The stages of one task in order: begin("simulate"), update(0.5), ..., begin("deskew"), end().
class StageReporter {
 public:
  /// `count`: how many stages the task will have, for the ETA.
  StageReporter(std::string task, int count);
  ~StageReporter();  ///< ends the open stage
  /// Ends the open stage, if any, and starts `stage`.
  void begin(const std::string& stage);
  /// How far through the open stage, in [0, 1].
  void update(double fraction) const;
  void end();

 private:
  std::string task_, stage_;
  int count_, index_ = -1;
  bool open_ = false;
};

/// Stage reports as one tab-separated line, and back (the runner's pipe).
std::string encodeStageEvent(const StageEvent& event);
bool decodeStageEvent(const std::string& line, StageEvent& event);

}  // namespace slamprep
