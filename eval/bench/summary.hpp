#pragma once
// Aggregating trial results: the suite summary (summary.json), the per-trial table (trials.csv),
// regression comparison against a committed baseline, and merging of shards.

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slamprep/eval/bench/suite.hpp"
#include "slamprep/eval/bench/suite_summary.hpp"

namespace slamprep::eval {

/// The trial results of a suite in trial order, and the ids that have none.
struct TrialSet {
  std::vector<nlohmann::json> results;
  std::vector<std::string> missing;
  std::vector<std::string> stale;  ///< files made for another spec or suite settings (missing)
};

/// Reads trials_dir/<id>.json for every trial (all shards). A result whose stored spec differs
/// from the trial's (the suite was edited since; the input digests are not compared, so a merge
/// needs no worlds) counts as missing and is listed in `stale`. Throws InputError naming the
/// file and field for one that is not a trial result (checkTrialShape).
TrialSet loadTrials(const std::vector<TrialSpec>& trials, const std::filesystem::path& trials_dir);

/// Refuses a result that lacks what summaries and tables read: "trial" with a string id, world
/// and scenario, a whole seed and a sweep object. Throws InputError("file: trial.key", ...).
void checkTrialShape(const nlohmann::json& result, const std::string& file);

/// A stored spec (specJson) without its "inputs" digests.
nlohmann::json withoutInputs(nlohmann::json trial_spec);

/// Numeric leaves of a result (bools as 0/1) by '/'-joined path, skipping the "trial" spec: the
/// generic part of the summary, which makes summary.json's metrics and trials.csv's columns from
/// whatever the records write. Code that reads one names it with trial_metrics.hpp.
std::map<std::string, double> flattenMetrics(const nlohmann::json& result);

/// What makes a group: one sweep point in one world and scenario, everything but the seed.
/// {world, scenario, sweep} of a trial spec (specJson).
nlohmann::json groupKey(const nlohmann::json& trial_spec);

/// summary.json: for every metric path its statistics over all trials, and the same per sweep
/// point (groups); per group also the calibration consistency over its seeds. Depends only on
/// the set of results, so shards merge to the same bytes as a single run.
SuiteSummary summarize(const Suite& suite, const TrialSet& set);

/// trials.csv: one row per trial (index order), one column per metric path (sorted).
std::string trialsCsv(const TrialSet& set);

/// A metric that got worse than its baseline by more than its tolerance allows.
struct Regression {
  std::string metric;
  double baseline = 0.0;
  double current = 0.0;
  double allowed = 0.0;  ///< the worst current value that would have passed
  std::string note;      ///< e.g. "missing from the current summary"
};

/// A results folder's summary.json, read and checked: InputError("file: field", ...) for one
/// unlike the ones bench writes (docs/results.md).
SuiteSummary readSuiteSummary(const std::filesystem::path& file);

/// The metric means of the --compare baseline, read and checked before any trial runs: a JSON
/// object whose "metrics" (if present) maps names to objects with a numeric "mean"
/// (baselineMeans). Throws InputError naming the file and field.
std::map<std::string, double> loadBaseline(const std::filesystem::path& file);

/// Compares the `mean` of each toleranced metric in its worse direction.
std::vector<Regression> compareToBaseline(const SuiteSummary& summary,
                                          const std::map<std::string, double>& baseline,
                                          const std::vector<Tolerance>& tolerances);

/// Copies the trial results of several shard folders into `trials_dir`; a trial present in two
/// shards must be byte-identical. Returns how many trial files were merged.
std::size_t mergeTrialFolders(const std::vector<std::filesystem::path>& shard_trials_dirs,
                              const std::filesystem::path& trials_dir);

}  // namespace slamprep::eval
