#include "slamprep/eval/bench/bench.hpp"

#include <cstdio>
#include <iostream>
#include <thread>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/json_input.hpp"
#include "slamprep/core/paths.hpp"
#include "slamprep/eval/bench/figures.hpp"
#include "slamprep/eval/bench/report.hpp"
#include "slamprep/eval/bench/results_folder.hpp"

namespace slamprep::eval {
namespace {

namespace fs = std::filesystem;

// Wall-clock figures of all trials, kept apart from the deterministic results.
nlohmann::json collectTiming(const std::vector<TrialSpec>& trials, const fs::path& timing_dir) {
  nlohmann::json timing = nlohmann::json::object();
  for (const auto& t : trials)
    if (fs::exists(timing_dir / (t.id + ".json")))
      timing[t.id] = readJsonFile(timing_dir / (t.id + ".json"), "timing file");
  return timing;
}

int defaultJobs() {
  return std::max(1u, std::thread::hardware_concurrency());
}

// Drops stored trials made by another build (or all of them with `fresh`), so resuming only
// ever skips work this very program did.
void invalidateStaleTrials(const fs::path& run_dir, bool fresh) {
  const fs::path stamp = run_dir / ".slamprep-build";
  const std::string current = binaryFingerprint();
  const bool stale = !fs::exists(stamp) || readFile(stamp) != current;
  if ((fresh || stale) && fs::exists(run_dir / "trials")) {
    if (!fresh)
      std::cerr << "results in " << run_dir.string() << " came from another build: recomputing\n";
    fs::remove_all(run_dir / "trials");
    fs::remove_all(run_dir / "timing");
  }
  writeFileAtomic(stamp, current);
}

// The plots (if asked) and the README that embeds them.
SuitePlots writeReport(const Suite& suite, const SuiteSummary& summary, const fs::path& dir,
                       bool plots) {
  SuitePlots written;
  if (plots) written = renderSuitePlots(suite, summary, dir);
  writeFileAtomic(dir / "README.md", renderReport(suite, summary, written.names));
  return written;
}

}  // namespace

std::string binaryFingerprint() {
  const std::string bytes = readFile("/proc/self/exe");
  std::uint64_t h = 1469598103934665603ull;
  for (unsigned char c : bytes) h = (h ^ c) * 1099511628211ull;
  char hex[17];
  std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
  return hex;
}

SuitePlots plotResults(const fs::path& results_dir) {
  for (const char* file : {"suite.yaml", "summary.json"})
    if (!fs::exists(results_dir / file))
      throw InputError((results_dir / file).string(),
                       "missing: not a finished results folder of `slamprep bench` (or `merge`)");
  requireResultsFolder(results_dir, "RESULTS_DIR");  // before anything is written into it
  const Suite suite = loadSuite(results_dir / "suite.yaml");
  const SuiteSummary summary = readSuiteSummary(results_dir / "summary.json");
  try {
    return writeReport(suite, summary, results_dir, true);
  } catch (const nlohmann::json::exception& e) {  // the first trial's artifacts, trials.csv
    throw InputError(results_dir.string(), std::string("unexpected content: ") + e.what());
  }
}

void writeResults(BenchOutcome& outcome, const std::vector<TrialSpec>& trials, bool plots) {
  const fs::path& dir = outcome.out_dir;
  const TrialSet set = loadTrials(trials, dir / "trials");
  for (const auto& file : set.stale)
    std::cerr << file << ": made for another version of the suite (or of this trial): not used\n";
  outcome.complete = set.missing.empty();
  try {
    outcome.summary = summarize(outcome.suite, set);
  } catch (const nlohmann::json::exception& e) {  // a result's metric of an unexpected type
    throw InputError((dir / "trials").string(),
                     std::string("a trial result has unexpected content: ") + e.what());
  }
  writeFileAtomic(dir / "summary.json", nlohmann::json(outcome.summary).dump(2) + "\n");
  writeFileAtomic(dir / "trials.csv", trialsCsv(set));
  writeFileAtomic(dir / "timing.json", collectTiming(trials, dir / "timing").dump(2) + "\n");
  outcome.plots = writeReport(outcome.suite, outcome.summary, dir, plots);
}

BenchOutcome runBench(const BenchOptions& options, const TrialFunction& trial) {
  BenchOutcome outcome;
  const fs::path suite_file = findSuite(options.suite, resolveDataPath("eval/suites"));
  outcome.suite = loadSuite(suite_file);
  outcome.out_dir = options.results_root / outcome.suite.name;
  // Read and checked before any trial runs: a bad baseline must not cost the suite's hours.
  const std::optional<std::map<std::string, double>> baseline =
      options.compare ? std::optional(loadBaseline(*options.compare)) : std::nullopt;
  auto trials = expandTrials(outcome.suite);
  attachInputDigests(trials);  // an edited world or scenario makes its trials stale

  claimResultsFolder(outcome.out_dir, "--results");  // never a folder bench did not create
  // The suite travels with its results, so `merge` can run anywhere the folder is.
  writeFileAtomic(outcome.out_dir / "suite.yaml", readFile(suite_file));
  const fs::path run_dir =
      options.shard ? outcome.out_dir / "shards" / options.shard->name() : outcome.out_dir;
  invalidateStaleTrials(run_dir, options.fresh);
  RunOptions run{options.jobs > 0 ? options.jobs : defaultJobs(), options.shard.value_or(Shard{}),
                 run_dir / "trials", run_dir / "timing", options.progress};
  outcome.run = runTrials(trials, trial, run);
  if (options.shard) return outcome;  // `slamprep merge` aggregates the shards

  writeResults(outcome, trials, options.plots);
  if (baseline)
    outcome.regressions = compareToBaseline(outcome.summary, *baseline, outcome.suite.tolerances);
  if (options.update_baseline)
    writeFileAtomic(outcome.out_dir / "baseline.json",
                    nlohmann::json(outcome.summary).dump(2) + "\n");
  return outcome;
}

BenchOutcome mergeShards(const fs::path& results_dir, bool plots) {
  BenchOutcome outcome;
  const fs::path suite_file = results_dir / "suite.yaml";
  if (!fs::exists(suite_file))
    throw InputError(results_dir.string(), "no suite.yaml: not a results folder of slamprep bench");
  requireResultsFolder(results_dir, "RESULTS_DIR");  // before anything is written into it
  outcome.suite = loadSuite(suite_file);
  outcome.out_dir = results_dir;
  std::vector<fs::path> shard_dirs;
  if (fs::is_directory(results_dir / "shards"))
    for (const auto& entry : fs::directory_iterator(results_dir / "shards"))
      if (fs::is_directory(entry.path() / "trials")) shard_dirs.push_back(entry.path() / "trials");
  std::sort(shard_dirs.begin(), shard_dirs.end());
  if (shard_dirs.empty()) throw InputError(results_dir.string(), "no shards/*/trials to merge");
  mergeTrialFolders(shard_dirs, results_dir / "trials");
  std::vector<fs::path> timing_dirs;
  for (const auto& d : shard_dirs) timing_dirs.push_back(d.parent_path() / "timing");
  for (const auto& d : timing_dirs)
    if (fs::is_directory(d))
      for (const auto& entry : fs::directory_iterator(d))
        writeFileAtomic(results_dir / "timing" / entry.path().filename(), readFile(entry.path()));
  writeResults(outcome, expandTrials(outcome.suite), plots);
  return outcome;
}

}  // namespace slamprep::eval
