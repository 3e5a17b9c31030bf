#include "slamprep/eval/bench/suite_summary.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <set>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/bench/group_consistency.hpp"
#include "slamprep/eval/bench/record_fields.hpp"
#include "slamprep/eval/bench/trial_metrics.hpp"

namespace slamprep::eval {
namespace {

using nlohmann::json;

// The one spelling of each key of summary.json.
enum class SummaryField { kFormatVersion, kSuite, kTrials, kMissing, kMetrics, kGroups };
enum class GroupField { kWorld, kScenario, kSweep, kTrials, kMetrics, kConsistency };
enum class StatField { kN, kMean, kStd, kMin, kMax };

constexpr auto kSummaryFieldKeys =
    std::to_array<EnumName<SummaryField>>({{SummaryField::kFormatVersion, "format_version"},
                                           {SummaryField::kSuite, "suite"},
                                           {SummaryField::kTrials, "trials"},
                                           {SummaryField::kMissing, "missing"},
                                           {SummaryField::kMetrics, "metrics"},
                                           {SummaryField::kGroups, "groups"}});
constexpr auto kGroupFieldKeys =
    std::to_array<EnumName<GroupField>>({{GroupField::kWorld, "world"},
                                         {GroupField::kScenario, "scenario"},
                                         {GroupField::kSweep, "sweep"},
                                         {GroupField::kTrials, "trials"},
                                         {GroupField::kMetrics, "metrics"},
                                         {GroupField::kConsistency, "consistency"}});
constexpr auto kStatFieldKeys = std::to_array<EnumName<StatField>>({{StatField::kN, "n"},
                                                                    {StatField::kMean, "mean"},
                                                                    {StatField::kStd, "std"},
                                                                    {StatField::kMin, "min"},
                                                                    {StatField::kMax, "max"}});

std::string key(SummaryField f) {
  return keyOf(kSummaryFieldKeys, f);
}
std::string key(GroupField f) {
  return keyOf(kGroupFieldKeys, f);
}
std::string key(StatField f) {
  return keyOf(kStatFieldKeys, f);
}

// ---- writing ----

json statsJson(const MetricStats& s) {
  return {{key(StatField::kN), s.n},
          {key(StatField::kMean), s.mean},
          {key(StatField::kStd), s.std},
          {key(StatField::kMin), s.min},
          {key(StatField::kMax), s.max}};
}

json metricsJson(const SummaryMetrics& metrics) {
  json out = json::object();
  for (const auto& [path, stats] : metrics) out[path] = statsJson(stats);
  return out;
}

// Flat, as the metrics: "calibration/<method>/consistency/<param>/<stat>" -> number.
json consistencyJson(const GroupConsistency& consistency) {
  json out = json::object();
  for (const auto& [method, m] : consistency) {
    for (const auto& [param_key, e] : m.params) {
      const CalibrationParam param = param_key;  // clang 14 captures no structured binding
      const std::string& name = method;
      const auto at = [&](ConsistencyStat stat) { return consistencyMetric(name, param, stat); };
      out[at(ConsistencyStat::kN)] = e.n;
      out[at(ConsistencyStat::kBias)] = e.bias;
      out[at(ConsistencyStat::kStd)] = e.std;
      out[at(ConsistencyStat::kRms)] = e.rms;
      out[at(ConsistencyStat::kCoverage1Sigma)] = e.coverage_1sigma;
      out[at(ConsistencyStat::kCoverage3Sigma)] = e.coverage_3sigma;
    }
    if (m.nees) {
      out[consistencyMetric(method, NeesStat::kMean)] = m.nees->mean;
      out[consistencyMetric(method, NeesStat::kN)] = m.nees->n;
    }
  }
  return out;
}

json groupJson(const SummaryGroup& g) {
  json out = {{key(GroupField::kWorld), g.world},
              {key(GroupField::kScenario), g.scenario},
              {key(GroupField::kSweep), g.sweep},
              {key(GroupField::kTrials), g.trials},
              {key(GroupField::kMetrics), metricsJson(g.metrics)}};
  if (!g.consistency.empty()) out[key(GroupField::kConsistency)] = consistencyJson(g.consistency);
  return out;
}

// ---- reading: every check names the field, "groups[0].metrics.<path>.mean" ----

[[noreturn]] void badField(const std::string& field, const std::string& what) {
  throw InputError(field, what);
}

const json& objectAt(const json& in, const std::string& k, const std::string& field) {
  if (!in.contains(k) || !in[k].is_object()) badField(field, "missing or not an object");
  return in[k];
}

std::string stringAt(const json& in, const std::string& k, const std::string& field) {
  if (!in.contains(k) || !in[k].is_string()) badField(field, "missing or not a string");
  return in[k].get<std::string>();
}

double numberAt(const json& in, const std::string& k, const std::string& field) {
  if (!in.contains(k) || !in[k].is_number()) badField(field, "missing or not a number");
  return in[k].get<double>();
}

// A whole number >= 0, parsed (unsigned) or written from a signed field (ErrorConsistency::n).
template <typename Count>
Count countAt(const json& in, const std::string& k, const std::string& field) {
  const bool whole = in.contains(k) && in[k].is_number_integer() &&
                     (in[k].is_number_unsigned() || in[k].get<std::int64_t>() >= 0);
  if (!whole) badField(field, "missing or not a whole number >= 0");
  return in[k].get<Count>();
}

MetricStats readStats(const json& in, const std::string& at) {
  if (!in.is_object()) badField(at, "not an object {n, mean, std, min, max}");
  const auto field = [&](StatField f) { return at + "." + key(f); };
  MetricStats s;
  s.mean = numberAt(in, key(StatField::kMean), field(StatField::kMean));
  s.std = numberAt(in, key(StatField::kStd), field(StatField::kStd));
  s.min = numberAt(in, key(StatField::kMin), field(StatField::kMin));
  s.max = numberAt(in, key(StatField::kMax), field(StatField::kMax));
  s.n = countAt<std::size_t>(in, key(StatField::kN), field(StatField::kN));
  return s;
}

SummaryMetrics readMetrics(const json& in, const std::string& at) {
  SummaryMetrics out;
  for (const auto& [path, stats] : in.items()) out[path] = readStats(stats, at + "." + path);
  return out;
}

// The statistics of one method and parameter, when the group has them; `used` collects the keys.
std::optional<ErrorConsistency> readParamConsistency(const json& in, const std::string& method,
                                                     CalibrationParam param, const std::string& at,
                                                     std::set<std::string>& used) {
  const auto k = [&](ConsistencyStat stat) { return consistencyMetric(method, param, stat); };
  if (!in.contains(k(ConsistencyStat::kN))) return std::nullopt;
  ErrorConsistency e;
  const auto number = [&](ConsistencyStat stat) {
    used.insert(k(stat));
    return numberAt(in, k(stat), at + "." + k(stat));
  };
  used.insert(k(ConsistencyStat::kN));
  e.n = countAt<int>(in, k(ConsistencyStat::kN), at + "." + k(ConsistencyStat::kN));
  e.bias = number(ConsistencyStat::kBias);
  e.std = number(ConsistencyStat::kStd);
  e.rms = number(ConsistencyStat::kRms);
  e.coverage_1sigma = number(ConsistencyStat::kCoverage1Sigma);
  e.coverage_3sigma = number(ConsistencyStat::kCoverage3Sigma);
  return e;
}

std::optional<NeesConsistency> readNees(const json& in, const std::string& method,
                                        const std::string& at, std::set<std::string>& used) {
  const std::string mean = consistencyMetric(method, NeesStat::kMean);
  const std::string n = consistencyMetric(method, NeesStat::kN);
  if (!in.contains(mean)) return std::nullopt;
  used.insert(mean);
  used.insert(n);
  return NeesConsistency{numberAt(in, mean, at + "." + mean),
                         countAt<std::size_t>(in, n, at + "." + n)};
}

GroupConsistency readConsistency(const json& in, const std::string& at) {
  if (!in.is_object()) badField(at, "not an object");
  std::set<std::string> methods, used;
  for (const auto& [k, value] : in.items()) {
    if (!value.is_number()) badField(at + "." + k, "not a number");
    methods.insert(methodOfMetric(TrialSection::kCalibration, k));
  }
  GroupConsistency out;
  for (const std::string& method : methods) {
    MethodConsistency m;
    for (const CalibrationParam param : kCalibrationParams)
      if (auto e = readParamConsistency(in, method, param, at, used)) m.params[param] = *e;
    m.nees = readNees(in, method, at, used);
    if (!m.params.empty() || m.nees) out[method] = std::move(m);
  }
  for (const auto& [k, _] : in.items())  // a key none of the above names
    if (!used.contains(k)) badField(at + "." + k, "not a consistency statistic");
  return out;
}

SummaryGroup readGroup(const json& in, const std::string& at) {
  if (!in.is_object()) badField(at, "not an object");
  const auto field = [&](GroupField f) { return at + "." + key(f); };
  SummaryGroup g;
  g.world = stringAt(in, key(GroupField::kWorld), field(GroupField::kWorld));
  g.scenario = stringAt(in, key(GroupField::kScenario), field(GroupField::kScenario));
  for (const auto& [k, value] :
       objectAt(in, key(GroupField::kSweep), field(GroupField::kSweep)).items()) {
    if (!value.is_string()) badField(field(GroupField::kSweep) + "." + k, "not a string");
    g.sweep[k] = value.get<std::string>();
  }
  g.trials = countAt<std::size_t>(in, key(GroupField::kTrials), field(GroupField::kTrials));
  g.metrics = readMetrics(objectAt(in, key(GroupField::kMetrics), field(GroupField::kMetrics)),
                          field(GroupField::kMetrics));
  if (in.contains(key(GroupField::kConsistency)))
    g.consistency =
        readConsistency(in[key(GroupField::kConsistency)], field(GroupField::kConsistency));
  return g;
}

std::vector<std::string> readMissing(const json& in) {
  const std::string k = key(SummaryField::kMissing);
  if (!in.contains(k) || !in[k].is_array()) badField(k, "missing or not an array");
  std::vector<std::string> out;
  for (std::size_t i = 0; i < in[k].size(); ++i) {
    if (!in[k][i].is_string()) badField(k + "[" + std::to_string(i) + "]", "not a string");
    out.push_back(in[k][i].get<std::string>());
  }
  return out;
}

}  // namespace

MetricStats metricStats(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  const double mean = sum / values.size();
  double sq = 0.0;
  for (double v : values) sq += (v - mean) * (v - mean);
  return {values.size(), mean, values.size() > 1 ? std::sqrt(sq / (values.size() - 1)) : 0.0,
          *std::min_element(values.begin(), values.end()),
          *std::max_element(values.begin(), values.end())};
}

void to_json(json& out, const SuiteSummary& s) {
  json groups = json::array();
  for (const SummaryGroup& g : s.groups) groups.push_back(groupJson(g));
  out = {{key(SummaryField::kFormatVersion), s.format_version},
         {key(SummaryField::kSuite), s.suite},
         {key(SummaryField::kTrials), s.trials},
         {key(SummaryField::kMissing), s.missing},
         {key(SummaryField::kMetrics), metricsJson(s.metrics)},
         {key(SummaryField::kGroups), std::move(groups)}};
}

void from_json(const json& in, SuiteSummary& s) {
  if (!in.is_object()) badField("", "a summary must be a JSON object");
  const std::string version = key(SummaryField::kFormatVersion);
  s.format_version = countAt<int>(in, version, version);
  if (s.format_version != kSummaryFormatVersion)
    badField(version, "this build reads version " + std::to_string(kSummaryFormatVersion));
  s.suite = stringAt(in, key(SummaryField::kSuite), key(SummaryField::kSuite));
  s.trials = countAt<std::size_t>(in, key(SummaryField::kTrials), key(SummaryField::kTrials));
  s.missing = readMissing(in);
  const std::string metrics = key(SummaryField::kMetrics);
  s.metrics = readMetrics(objectAt(in, metrics, metrics), metrics);
  const std::string groups = key(SummaryField::kGroups);
  if (!in.contains(groups) || !in[groups].is_array()) badField(groups, "missing or not an array");
  s.groups.clear();
  for (std::size_t i = 0; i < in[groups].size(); ++i)
    s.groups.push_back(readGroup(in[groups][i], groups + "[" + std::to_string(i) + "]"));
}

SuiteSummary parseSuiteSummary(const json& in, const std::string& file) {
  try {
    return in.get<SuiteSummary>();
  } catch (const InputError& e) {
    throw InputError(file, e.what());
  }
}

std::map<std::string, double> baselineMeans(const json& in, const std::string& file) {
  std::map<std::string, double> out;
  const std::string metrics = key(SummaryField::kMetrics);
  if (!in.contains(metrics)) return out;  // every toleranced metric is then missing (exit 3)
  if (!in[metrics].is_object()) badField(file + ": " + metrics, "missing or not an object");
  for (const auto& [path, stats] : in[metrics].items()) {
    const std::string at = file + ": " + metrics + "." + path;
    if (!stats.is_object()) badField(at, "not an object {n, mean, std, min, max}");
    out[path] = numberAt(stats, key(StatField::kMean), at + "." + key(StatField::kMean));
  }
  return out;
}

}  // namespace slamprep::eval
