#include "slamprep/eval/bench/summary.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/json_input.hpp"
#include "slamprep/eval/bench/group_consistency.hpp"
#include "slamprep/eval/bench/runner.hpp"
#include "slamprep/eval/bench/trial_record.hpp"

namespace slamprep::eval {
namespace {

void flattenInto(const nlohmann::json& node, const std::string& path,
                 std::map<std::string, double>& out) {
  if (node.is_object()) {
    for (const auto& [key, value] : node.items())
      if (!(path.empty() && key == sectionKey(TrialSection::kTrial)))
        flattenInto(value, path.empty() ? key : path + "/" + key, out);
  } else if (node.is_number()) {
    const double v = node.get<double>();
    if (std::isfinite(v)) out[path] = v;
  } else if (node.is_boolean()) {
    out[path] = node.get<bool>() ? 1.0 : 0.0;
  }
}

// Metric path -> its statistics over the given results.
SummaryMetrics statsOver(const std::vector<const nlohmann::json*>& results) {
  std::map<std::string, std::vector<double>> values;
  for (const auto* r : results)
    for (const auto& [path, v] : flattenMetrics(*r)) values[path].push_back(v);
  SummaryMetrics out;
  for (const auto& [path, v] : values) out[path] = metricStats(v);
  return out;
}

}  // namespace

TrialSet loadTrials(const std::vector<TrialSpec>& trials, const std::filesystem::path& trials_dir) {
  TrialSet set;
  for (const auto& spec : trials) {
    const auto file = trials_dir / (spec.id + ".json");
    if (!std::filesystem::exists(file)) {
      set.missing.push_back(spec.id);
      continue;
    }
    nlohmann::json result = readJsonFile(file, "trial result");
    checkTrialShape(result, file.string());
    if (withoutInputs(result["trial"]) != withoutInputs(specJson(spec))) {
      set.missing.push_back(spec.id);  // made by another version of the suite: never mixed in
      set.stale.push_back(file.string());
      continue;
    }
    set.results.push_back(std::move(result));
  }
  return set;
}

void checkTrialShape(const nlohmann::json& result, const std::string& file) {
  if (!result.is_object()) throw InputError(file, "a trial result must be a JSON object");
  if (!result.contains("trial") || !result["trial"].is_object())
    throw InputError(file + ": trial", "missing or not an object (the trial's spec)");
  const nlohmann::json& t = result["trial"];
  for (const char* key : {"id", "world", "scenario"})
    if (!t.contains(key) || !t[key].is_string())
      throw InputError(file + ": trial." + key, "missing or not a string");
  if (!t.contains("seed") || !t["seed"].is_number_unsigned())
    throw InputError(file + ": trial.seed", "missing or not a whole number >= 0");
  if (!t.contains("sweep") || !t["sweep"].is_object())
    throw InputError(file + ": trial.sweep", "missing or not an object");
}

nlohmann::json withoutInputs(nlohmann::json trial_spec) {
  if (trial_spec.is_object()) trial_spec.erase("inputs");
  return trial_spec;
}

SuiteSummary readSuiteSummary(const std::filesystem::path& file) {
  return parseSuiteSummary(readJsonFile(file, "summary"), file.string());
}

std::map<std::string, double> loadBaseline(const std::filesystem::path& file) {
  const nlohmann::json baseline = readJsonFile(file, "baseline summary");
  if (!baseline.is_object()) throw InputError(file.string(), "a baseline must be a JSON object");
  return baselineMeans(baseline, file.string());
}

std::map<std::string, double> flattenMetrics(const nlohmann::json& result) {
  std::map<std::string, double> out;
  flattenInto(result, "", out);
  return out;
}

nlohmann::json groupKey(const nlohmann::json& trial_spec) {
  return {{"world", trial_spec.value("world", nlohmann::json())},
          {"scenario", trial_spec.value("scenario", nlohmann::json())},
          {"sweep", trial_spec.value("sweep", nlohmann::json())}};
}

SuiteSummary summarize(const Suite& suite, const TrialSet& set) {
  std::vector<const nlohmann::json*> all;
  std::map<std::string, std::vector<const nlohmann::json*>> by_group;  // by key, as JSON text
  for (const auto& r : set.results) {
    all.push_back(&r);
    by_group[groupKey(r["trial"]).dump()].push_back(&r);
  }
  SuiteSummary summary{kSummaryFormatVersion, suite.name,     set.results.size(),
                       set.missing,           statsOver(all), {}};
  for (const auto& [_, members] : by_group) {
    const nlohmann::json& spec = (*members.front())["trial"];
    summary.groups.push_back({spec["world"].get<std::string>(), spec["scenario"].get<std::string>(),
                              spec["sweep"].get<std::map<std::string, std::string>>(),
                              members.size(), statsOver(members), consistencyOver(members)});
  }
  return summary;
}

std::string trialsCsv(const TrialSet& set) {
  std::vector<std::map<std::string, double>> rows;
  std::set<std::string> columns;
  for (const auto& r : set.results) {
    rows.push_back(flattenMetrics(r));
    for (const auto& [path, v] : rows.back()) columns.insert(path);
  }
  std::ostringstream csv;
  csv << "id,world,scenario,seed";
  for (const auto& c : columns) csv << ',' << c;
  csv << '\n';
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const auto& t = set.results[i]["trial"];
    csv << t["id"].get<std::string>() << ',' << t["world"].get<std::string>() << ','
        << t["scenario"].get<std::string>() << ',' << t["seed"].get<std::uint64_t>();
    for (const auto& c : columns) {
      csv << ',';
      if (auto it = rows[i].find(c); it != rows[i].end()) csv << nlohmann::json(it->second).dump();
    }
    csv << '\n';
  }
  return csv.str();
}

std::vector<Regression> compareToBaseline(const SuiteSummary& summary,
                                          const std::map<std::string, double>& baseline,
                                          const std::vector<Tolerance>& tolerances) {
  std::vector<Regression> out;
  for (const auto& tol : tolerances) {
    const auto base_it = baseline.find(tol.metric);
    const auto cur_it = summary.metrics.find(tol.metric);
    const bool has_cur = cur_it != summary.metrics.end();
    if (base_it == baseline.end()) {
      out.push_back(
          {tol.metric, 0, has_cur ? cur_it->second.mean : 0, 0, "missing from the baseline"});
      continue;
    }
    const double base = base_it->second;
    if (!has_cur) {
      out.push_back({tol.metric, base, 0, 0, "missing from the current run"});
      continue;
    }
    const double cur = cur_it->second.mean;
    const double slack = std::max(tol.abs, tol.rel * std::abs(base));
    const double allowed = tol.higher_is_better ? base - slack : base + slack;
    const bool worse = tol.higher_is_better ? cur < allowed : cur > allowed;
    if (worse) out.push_back({tol.metric, base, cur, allowed, ""});
  }
  return out;
}

std::size_t mergeTrialFolders(const std::vector<std::filesystem::path>& shard_trials_dirs,
                              const std::filesystem::path& trials_dir) {
  std::map<std::string, std::string> merged;  // file name -> content
  for (const auto& dir : shard_trials_dirs) {
    if (!std::filesystem::is_directory(dir)) throw InputError(dir.string(), "no such shard folder");
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(dir))
      if (entry.path().extension() == ".json") files.push_back(entry.path());
    std::sort(files.begin(), files.end());
    for (const auto& file : files) {
      const std::string text = readFile(file);
      const auto [it, inserted] = merged.emplace(file.filename().string(), text);
      if (!inserted && it->second != text)
        throw InputError(file.string(), "differs from the same trial in another shard");
    }
  }
  for (const auto& [name, text] : merged) {
    const auto target = trials_dir / name;
    if (std::filesystem::exists(target) && readFile(target) == text) continue;
    writeFileAtomic(target, text);
  }
  return merged.size();
}

}  // namespace slamprep::eval
