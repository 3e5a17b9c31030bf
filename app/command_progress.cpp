#include "slamprep/app/command_progress.hpp"

#include <chrono>

namespace slamprep::app {
namespace {

ProgressOptions commandOptions(std::string label, bool enabled) {
  return {.style = progressStyleFor(enabled ? stderr : nullptr),
          .label = std::move(label),
          .quiet_for_s = 2.0};
}

void writeStderr(const std::string& text) {
  std::fputs(text.c_str(), stderr);
  std::fflush(stderr);
}

}  // namespace

CommandProgress::CommandProgress(std::size_t total, std::string unit, std::string label,
                                 bool enabled)
    : progress_(total, std::move(unit), commandOptions(std::move(label), enabled), writeStderr,
                steadySeconds),
      sink_([this](const StageEvent& e) {
        const std::lock_guard lock(mutex_);
        progress_.stage(e);
      }),
      ticker_([this](std::stop_token stop) {
        std::unique_lock lock(mutex_);
        while (!stop.stop_requested()) {
          wake_.wait_for(lock, stop, std::chrono::milliseconds(100), [] { return false; });
          if (!stop.stop_requested()) progress_.tick();
        }
      }) {}

CommandProgress::~CommandProgress() {
  ticker_.request_stop();
  ticker_.join();
  progress_.finish("");
}

void CommandProgress::advance(const std::string& task) {
  const std::lock_guard lock(mutex_);
  progress_.advance(1, task);
}

void CommandProgress::clearLine() {
  const std::lock_guard lock(mutex_);
  progress_.clearLine();
}

}  // namespace slamprep::app
