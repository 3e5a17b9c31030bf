#pragma once
// A single command's progress (simulate, match, calibrate, deskew): this process's stage reports
// (stage_report.hpp) on stderr, shown only once the command has run for 2 s, kept fresh by a
// ticker thread so that a long stage without reports still shows its elapsed time.

#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "slamprep/core/progress.hpp"
#include "slamprep/core/stage_report.hpp"

namespace slamprep::app {

class CommandProgress {
 public:
  /// `total` tasks named `unit` ("methods"); `label` is the command; silent unless `enabled`.
  CommandProgress(std::size_t total, std::string unit, std::string label, bool enabled = true);
  ~CommandProgress();  ///< stops the ticker and ends the bar
  CommandProgress(const CommandProgress&) = delete;
  CommandProgress& operator=(const CommandProgress&) = delete;

  /// Task `task` is done.
  void advance(const std::string& task);
  /// Wipes the bar before a line goes to stdout.
  void clearLine();

 private:
  std::mutex mutex_;
  Progress progress_;
  ScopedStageSink sink_;
  std::condition_variable_any wake_;
  std::jthread ticker_;
};

}  // namespace slamprep::app
