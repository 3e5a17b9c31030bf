#pragma once
// `slamprep bench`: run a suite's trials, aggregate them into results/<suite>/, render the report
// and plots, and compare against a committed baseline.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/eval/bench/figures.hpp"
#include "slamprep/eval/bench/runner.hpp"
#include "slamprep/eval/bench/summary.hpp"

namespace slamprep::eval {

struct BenchOptions {
  std::string suite = "default";                   ///< suite name under eval/suites/, or a file
  int jobs = 0;                                    ///< worker processes; 0: one per core
  std::optional<Shard> shard;                      ///< run one slice into shards/K-of-N/
  std::filesystem::path results_root = "results";  ///< results/<suite>/ goes below it
  std::optional<std::filesystem::path> compare;    ///< baseline summary to compare against
  bool update_baseline = false;                    ///< write summary.json as the new baseline
  bool plots = true;                               ///< render PNG plots into plots/
  bool progress = true;                            ///< progress bar / lines on stderr
  bool fresh = false;                              ///< recompute even trials this build finished
};

struct BenchOutcome {
  Suite suite;
  std::filesystem::path out_dir;
  RunReport run;
  bool complete = false;  ///< every trial of the suite has a result
  SuiteSummary summary;   ///< empty for a shard run
  std::vector<Regression> regressions;
  SuitePlots plots;  ///< file names under out_dir/plots
};

/// Runs the suite (or its shard) with `trial` and, when complete, writes the results folder.
BenchOutcome runBench(const BenchOptions& options, const TrialFunction& trial);

/// Merges results/<suite>/shards/*/ into results/<suite>/ and writes the results folder, exactly
/// as a single-machine run would have. `results_dir` holds the suite.yaml a bench run left there.
BenchOutcome mergeShards(const std::filesystem::path& results_dir, bool plots);

/// FNV-1a of the running executable, the stamp a run leaves beside its trials: results computed
/// by other code are never reused.
std::string binaryFingerprint();

/// `slamprep plot`: renders the plots of a results folder (suite.yaml, summary.json, trials/)
/// into plots/ and rewrites its README.md around them; returns the plots it names. Without
/// trials/ the figures drawn from it keep their existing PNGs (renderSuitePlots).
SuitePlots plotResults(const std::filesystem::path& results_dir);

/// Writes trials.csv, summary.json, timing.json, README.md and plots/ for a complete suite run.
void writeResults(BenchOutcome& outcome, const std::vector<TrialSpec>& trials, bool plots);

}  // namespace slamprep::eval
