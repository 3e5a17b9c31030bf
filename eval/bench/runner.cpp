#include "slamprep/eval/bench/runner.hpp"

#include <fcntl.h>
#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <iostream>
#include <map>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/json_input.hpp"
#include "slamprep/core/progress.hpp"
#include "slamprep/core/stage_report.hpp"

namespace slamprep::eval {
namespace {

// A child's stage reports, one line each down the pipe (lines below PIPE_BUF are written whole
// even when several children share it); updates at most every 0.2 s.
StageSink pipeSink(int fd) {
  return [fd, last = std::chrono::steady_clock::time_point()](const StageEvent& e) mutable {
    const auto now = std::chrono::steady_clock::now();
    if (e.kind == StageEvent::kUpdate && now - last < std::chrono::milliseconds(200)) return;
    last = now;
    const std::string line = encodeStageEvent(e);
    if (::write(fd, line.data(), line.size()) < 0) return;  // progress only: never fails a trial
  };
}

// Feeds every complete line waiting in the (non-blocking) pipe to `progress`.
void drainStageReports(int fd, std::string& buffer, Progress& progress) {
  char chunk[4096];
  for (ssize_t n; (n = ::read(fd, chunk, sizeof chunk)) > 0;) buffer.append(chunk, n);
  std::size_t begin = 0;
  for (std::size_t end; (end = buffer.find('\n', begin)) != std::string::npos; begin = end + 1) {
    StageEvent event;
    if (decodeStageEvent(buffer.substr(begin, end - begin), event)) progress.stage(event);
  }
  buffer.erase(0, begin);
}

// Waits for any child to end, showing its stage reports meanwhile.
pid_t waitForChild(int& status, int fd, std::string& buffer, Progress& progress) {
  for (;;) {
    const pid_t pid = ::waitpid(-1, &status, WNOHANG);
    if (pid != 0) {
      drainStageReports(fd, buffer, progress);
      return pid;
    }
    pollfd readable{fd, POLLIN, 0};
    ::poll(&readable, 1, 100);
    drainStageReports(fd, buffer, progress);
    progress.tick();
  }
}

// Runs one trial in this (child) process and writes its files; returns the exit status.
int runChild(const TrialSpec& spec, const TrialFunction& run, const RunOptions& options,
             int report_fd) {
  const ScopedStageSink sink(pipeSink(report_fd));
  try {
    TrialOutput out = run(spec);
    out.result["trial"] = specJson(spec);
    writeFileAtomic(options.timing_dir / (spec.id + ".json"), out.timing.dump(2) + "\n");
    writeFileAtomic(options.trials_dir / (spec.id + ".json"), out.result.dump(2) + "\n");
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "\ntrial " << spec.id << " failed: " << e.what() << "\n";
    return 3;
  }
}

}  // namespace

bool isTrialComplete(const std::filesystem::path& file, const TrialSpec& spec) {
  if (!std::filesystem::exists(file)) return false;
  try {
    const auto stored = readJsonFile(file, "trial result");
    return stored.is_object() && stored.contains("trial") && stored["trial"] == specJson(spec);
  } catch (const std::exception&) {  // unreadable or malformed: computed again
    return false;
  }
}

Shard Shard::parse(const std::string& text, const std::string& flag) {
  Shard shard;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%d/%d%c", &shard.index, &shard.count, &tail) != 2 ||
      shard.count < 1 || shard.index < 1 || shard.index > shard.count)
    throw InputError(flag + " " + text, "expected K/N with 1 <= K <= N, e.g. 2/8");
  return shard;
}

std::string Shard::name() const {
  return std::to_string(index) + "-of-" + std::to_string(count);
}

nlohmann::json specJson(const TrialSpec& spec) {
  return {{"id", spec.id},
          {"index", spec.index},
          {"world", spec.world},
          {"scenario", spec.scenario},
          {"seed", spec.seed},
          {"duration_s", spec.duration_s},
          {"overrides", spec.overrides},
          {"sweep", spec.sweep},
          {"settings", spec.settings},
          {"inputs", spec.inputs}};
}

RunReport runTrials(const std::vector<TrialSpec>& trials, const TrialFunction& run,
                    const RunOptions& options) {
  const auto start = std::chrono::steady_clock::now();
  std::filesystem::create_directories(options.trials_dir);
  std::filesystem::create_directories(options.timing_dir);

  RunReport report;
  std::deque<const TrialSpec*> pending;
  for (const auto& spec : trials) {
    if (!options.shard.contains(spec.index)) continue;
    ++report.selected;
    if (isTrialComplete(options.trials_dir / (spec.id + ".json"), spec))
      ++report.reused;
    else
      pending.push_back(&spec);
  }

  Progress progress(pending.size(), "trials", options.show_progress ? stderr : nullptr);
  int reports[2];  // children's stage reports -> this process
  if (::pipe(reports) != 0) throw std::runtime_error("pipe failed");
  ::fcntl(reports[0], F_SETFL, ::fcntl(reports[0], F_GETFL) | O_NONBLOCK);
  std::string report_buffer;
  std::map<pid_t, const TrialSpec*> running;
  std::fflush(nullptr);  // children must not inherit unflushed output
  while (!pending.empty() || !running.empty()) {
    while (!pending.empty() && static_cast<int>(running.size()) < std::max(1, options.jobs)) {
      const TrialSpec* spec = pending.front();
      pending.pop_front();
      const pid_t pid = ::fork();
      if (pid < 0) throw std::runtime_error("fork failed");
      if (pid == 0) {
        ::close(reports[0]);
        ::_exit(runChild(*spec, run, options, reports[1]));
      }
      running[pid] = spec;
    }
    int status = 0;
    const pid_t pid = waitForChild(status, reports[0], report_buffer, progress);
    if (pid < 0) throw std::runtime_error("waitpid failed");
    const TrialSpec* spec = running.at(pid);
    running.erase(pid);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
      ++report.computed;
    else
      report.failed.push_back(spec->id);
    progress.advance(1, spec->id);
  }
  ::close(reports[0]);
  ::close(reports[1]);
  if (!report.failed.empty() || report.computed) progress.finish("");
  std::sort(report.failed.begin(), report.failed.end());
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace slamprep::eval
