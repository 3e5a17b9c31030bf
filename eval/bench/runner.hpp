#pragma once
// Runs a suite's trials in parallel worker processes, each deterministic from its spec, so the
// results are the same bytes whatever the job count or sharding. Trials run in forked processes
// rather than threads: Debian's Bullet is not built thread-safe and keeps global profiler state.

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slamprep/eval/bench/suite.hpp"

namespace slamprep::eval {

/// A disjoint slice of a suite: trial i belongs to shard (i mod count) + 1.
struct Shard {
  int index = 1;  ///< 1-based
  int count = 1;

  bool contains(std::size_t trial_index) const {
    return static_cast<int>(trial_index % count) == index - 1;
  }
  /// Parses "K/N" (1 <= K <= N); throws InputError naming `flag`.
  static Shard parse(const std::string& text, const std::string& flag = "--shard");
  std::string name() const;  ///< "K-of-N", a folder name
};

/// What one trial produced: `result` must depend on the spec alone (it is compared byte for
/// byte); `timing` holds wall-clock figures, kept apart so they never enter the comparison.
struct TrialOutput {
  nlohmann::json result;
  nlohmann::json timing;
};

using TrialFunction = std::function<TrialOutput(const TrialSpec&)>;

struct RunOptions {
  int jobs = 1;                      ///< worker processes at once
  Shard shard;                       ///< which slice of the trials to run
  std::filesystem::path trials_dir;  ///< <id>.json per trial; existing ones are reused
  std::filesystem::path timing_dir;  ///< <id>.json wall-clock figures per trial
  bool show_progress = true;
};

struct RunReport {
  std::size_t selected = 0;  ///< trials in this shard
  std::size_t reused = 0;    ///< already complete on disk (resumed)
  std::size_t computed = 0;
  std::vector<std::string> failed;  ///< ids of trials whose worker failed
  double seconds = 0.0;
};

/// Runs every trial of `shard` that has no complete result yet; a trial's result is written
/// atomically to trials_dir/<id>.json only when it succeeded, so an interrupted run resumes.
RunReport runTrials(const std::vector<TrialSpec>& trials, const TrialFunction& run,
                    const RunOptions& options);

/// A stored trial result is reusable when it parses and was made from the same spec: the same
/// trial, suite settings and world and scenario file digests (specJson).
bool isTrialComplete(const std::filesystem::path& file, const TrialSpec& spec);

/// The spec as stored with its result ("trial"), so a stale result (suite or its worlds and
/// scenarios changed) is recomputed. Only world, scenario, sweep, id and seed reach the summary.
nlohmann::json specJson(const TrialSpec& spec);

}  // namespace slamprep::eval
