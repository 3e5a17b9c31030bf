#pragma once
// A suite's summary (summary.json, docs/results.md "Summary"): every metric's statistics over
// all trials and per group (one world, scenario and sweep point over its seeds), and each group's
// calibration consistency. One to_json writes it and one from_json reads it back to the same
// bytes; the report and the figures read its fields, so a renamed statistic fails to compile.

#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/eval/bench/calibration_param.hpp"
#include "slamprep/eval/metrics/consistency.hpp"

namespace slamprep::eval {

/// One metric over the trials of the suite or of a group: summary.json's {n, mean, std, min, max}.
struct MetricStats {
  std::size_t n = 0;  ///< trials that have the metric
  double mean = 0.0;
  double std = 0.0;  ///< sample standard deviation (n - 1); 0 for one trial
  double min = 0.0;
  double max = 0.0;

  bool operator==(const MetricStats&) const = default;
};

/// The statistics of `values` (at least one).
MetricStats metricStats(const std::vector<double>& values);

/// Metric path (trial_metrics.hpp names them) -> its statistics.
using SummaryMetrics = std::map<std::string, MetricStats>;

/// A method's mean NEES over the group's trials that have one, and how many did.
struct NeesConsistency {
  double mean = 0.0;
  std::size_t n = 0;

  bool operator==(const NeesConsistency&) const = default;
};

/// One calibration method's consistency over a group: per parameter it reports a sigma for, the
/// signed error against that sigma, and the mean NEES.
struct MethodConsistency {
  std::map<CalibrationParam, ErrorConsistency> params;
  std::optional<NeesConsistency> nees;

  bool operator==(const MethodConsistency&) const = default;
};

/// Per calibration method; only methods with a parameter or a NEES are in it.
using GroupConsistency = std::map<std::string, MethodConsistency>;

/// One sweep point of one world and scenario, over its seeds.
struct SummaryGroup {
  std::string world;
  std::string scenario;
  std::map<std::string, std::string> sweep;  ///< the sweep values that make the group
  std::size_t trials = 0;
  SummaryMetrics metrics;
  GroupConsistency consistency;  ///< not written when empty

  bool operator==(const SummaryGroup&) const = default;
};

/// summary.json.
struct SuiteSummary {
  int format_version = 1;
  std::string suite;
  std::size_t trials = 0;            ///< trials with a result
  std::vector<std::string> missing;  ///< ids of the trials without one
  SummaryMetrics metrics;            ///< over all trials
  std::vector<SummaryGroup> groups;  ///< in the order of their key (groupKey) as JSON text

  bool operator==(const SuiteSummary&) const = default;
};

/// The format_version this build writes and reads.
inline constexpr int kSummaryFormatVersion = 1;

void to_json(nlohmann::json& out, const SuiteSummary& s);
/// Throws InputError("<field>", ...) naming the field ("groups[0].world") that is missing or of
/// the wrong type; parseSuiteSummary adds the file.
void from_json(const nlohmann::json& in, SuiteSummary& s);

/// from_json with the file in the message: InputError("file: groups[0].world", ...).
SuiteSummary parseSuiteSummary(const nlohmann::json& in, const std::string& file);

/// The metric means of a --compare baseline, read leniently: a summary.json of which only
/// "metrics".<path>."mean" is required (none without "metrics"). Throws InputError naming the
/// file and field.
std::map<std::string, double> baselineMeans(const nlohmann::json& in, const std::string& file);

}  // namespace slamprep::eval
