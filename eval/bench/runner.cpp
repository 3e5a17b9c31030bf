#include "eval/bench/runner.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <deque>
#include <iostream>
#include <map>

#include "core/atomic_file.hpp"
#include "core/error.hpp"
#include "eval/bench/progress.hpp"

namespace slamprep::eval {
namespace {

// Runs one trial in this (child) process and writes its files; returns the exit status.
int runChild(const TrialSpec& spec, const TrialFunction& run, const RunOptions& options) {
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
    const auto stored = nlohmann::json::parse(readFile(file));
    return stored.contains("trial") && stored["trial"] == specJson(spec);
  } catch (const std::exception&) {
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
          {"sweep", spec.sweep}};
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
  std::map<pid_t, const TrialSpec*> running;
  std::fflush(nullptr);  // children must not inherit unflushed output
  while (!pending.empty() || !running.empty()) {
    while (!pending.empty() && static_cast<int>(running.size()) < std::max(1, options.jobs)) {
      const TrialSpec* spec = pending.front();
      pending.pop_front();
      const pid_t pid = ::fork();
      if (pid < 0) throw std::runtime_error("fork failed");
      if (pid == 0) ::_exit(runChild(*spec, run, options));
      running[pid] = spec;
    }
    int status = 0;
    const pid_t pid = ::waitpid(-1, &status, 0);
    if (pid < 0) throw std::runtime_error("waitpid failed");
    const TrialSpec* spec = running.at(pid);
    running.erase(pid);
    if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
      ++report.computed;
    else
      report.failed.push_back(spec->id);
    progress.advance(1, spec->id);
  }
  if (!report.failed.empty() || report.computed) progress.finish("");
  std::sort(report.failed.begin(), report.failed.end());
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return report;
}

}  // namespace slamprep::eval
