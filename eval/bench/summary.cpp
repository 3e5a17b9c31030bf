#include "slamprep/eval/bench/summary.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <string_view>

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

nlohmann::json statsOf(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  const double mean = sum / values.size();
  double sq = 0.0;
  for (double v : values) sq += (v - mean) * (v - mean);
  return {{"n", values.size()},
          {"mean", mean},
          {"std", values.size() > 1 ? std::sqrt(sq / (values.size() - 1)) : 0.0},
          {"min", *std::min_element(values.begin(), values.end())},
          {"max", *std::max_element(values.begin(), values.end())}};
}

// Metric path -> stats over the given results.
nlohmann::json statsOver(const std::vector<const nlohmann::json*>& results) {
  std::map<std::string, std::vector<double>> values;
  for (const auto* r : results)
    for (const auto& [path, v] : flattenMetrics(*r)) values[path].push_back(v);
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [path, v] : values) out[path] = statsOf(v);
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

namespace {

[[noreturn]] void badField(const std::string& file, const std::string& field,
                           const std::string& what) {
  throw InputError(file + ": " + field, what);
}

// {name: {n, mean, std, min, max}}; with `mean_only` (a baseline) only the mean is required.
void checkMetrics(const nlohmann::json& metrics, const std::string& file, const std::string& field,
                  bool mean_only) {
  if (!metrics.is_object()) badField(file, field, "missing or not an object");
  for (const auto& [name, stats] : metrics.items()) {
    const std::string at = field + "." + name;
    if (!stats.is_object()) badField(file, at, "not an object {n, mean, std, min, max}");
    for (const char* key : {"mean", "std", "min", "max"}) {
      if (mean_only && std::string_view(key) != "mean") continue;
      if (!stats.contains(key) || !stats[key].is_number())
        badField(file, at + "." + key, "missing or not a number");
    }
    if (!mean_only && (!stats.contains("n") || !stats["n"].is_number_unsigned()))
      badField(file, at + ".n", "missing or not a whole number >= 0");
  }
}

void checkGroup(const nlohmann::json& g, const std::string& file, const std::string& at) {
  if (!g.is_object()) badField(file, at, "not an object");
  for (const char* key : {"world", "scenario"})
    if (!g.contains(key) || !g[key].is_string())
      badField(file, at + "." + key, "missing or not a string");
  if (!g.contains("sweep") || !g["sweep"].is_object())
    badField(file, at + ".sweep", "missing or not an object");
  for (const auto& [key, value] : g["sweep"].items())
    if (!value.is_string()) badField(file, at + ".sweep." + key, "not a string");
  if (!g.contains("trials") || !g["trials"].is_number_unsigned())
    badField(file, at + ".trials", "missing or not a whole number >= 0");
  checkMetrics(g.value("metrics", nlohmann::json()), file, at + ".metrics", false);
  if (!g.contains("consistency")) return;
  if (!g["consistency"].is_object()) badField(file, at + ".consistency", "not an object");
  for (const auto& [key, value] : g["consistency"].items())
    if (!value.is_number()) badField(file, at + ".consistency." + key, "not a number");
}

}  // namespace

void checkSummaryShape(const nlohmann::json& summary, const std::string& file) {
  if (!summary.is_object()) throw InputError(file, "a summary must be a JSON object");
  if (!summary.contains("trials") || !summary["trials"].is_number_unsigned())
    badField(file, "trials", "missing or not a whole number >= 0");
  if (!summary.contains("missing") || !summary["missing"].is_array())
    badField(file, "missing", "missing or not an array");
  checkMetrics(summary.value("metrics", nlohmann::json()), file, "metrics", false);
  if (!summary.contains("groups") || !summary["groups"].is_array())
    badField(file, "groups", "missing or not an array");
  for (std::size_t i = 0; i < summary["groups"].size(); ++i)
    checkGroup(summary["groups"][i], file, "groups[" + std::to_string(i) + "]");
}

nlohmann::json loadBaseline(const std::filesystem::path& file) {
  const nlohmann::json baseline = readJsonFile(file, "baseline summary");
  if (!baseline.is_object()) throw InputError(file.string(), "a baseline must be a JSON object");
  // Without "metrics" every toleranced metric is "missing from the baseline" (exit 3).
  if (baseline.contains("metrics"))
    checkMetrics(baseline["metrics"], file.string(), "metrics", true);
  return baseline;
}

std::map<std::string, double> flattenMetrics(const nlohmann::json& result) {
  std::map<std::string, double> out;
  flattenInto(result, "", out);
  return out;
}

nlohmann::json groupKey(const nlohmann::json& trial_or_group) {
  return {{"world", trial_or_group.value("world", nlohmann::json())},
          {"scenario", trial_or_group.value("scenario", nlohmann::json())},
          {"sweep", trial_or_group.value("sweep", nlohmann::json())}};
}

nlohmann::json summarize(const Suite& suite, const TrialSet& set) {
  std::vector<const nlohmann::json*> all;
  std::map<std::string, std::vector<const nlohmann::json*>> by_group;
  std::map<std::string, nlohmann::json> group_keys;
  for (const auto& r : set.results) {
    all.push_back(&r);
    const nlohmann::json key = groupKey(r["trial"]);
    by_group[key.dump()].push_back(&r);
    group_keys[key.dump()] = key;
  }
  nlohmann::json groups = nlohmann::json::array();
  for (const auto& [k, members] : by_group) {
    nlohmann::json g = group_keys[k];
    g["trials"] = members.size();
    g["metrics"] = statsOver(members);
    if (auto c = consistencyOver(members); !c.empty()) g["consistency"] = std::move(c);
    groups.push_back(g);
  }
  return {{"format_version", 1},    {"suite", suite.name},       {"trials", set.results.size()},
          {"missing", set.missing}, {"metrics", statsOver(all)}, {"groups", groups}};
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

std::vector<Regression> compareToBaseline(const nlohmann::json& summary,
                                          const nlohmann::json& baseline,
                                          const std::vector<Tolerance>& tolerances) {
  std::vector<Regression> out;
  const auto mean = [](const nlohmann::json& s,
                       const std::string& metric) -> std::optional<double> {
    if (!s.contains("metrics") || !s["metrics"].contains(metric)) return std::nullopt;
    return s["metrics"][metric]["mean"].get<double>();
  };
  for (const auto& tol : tolerances) {
    const auto base = mean(baseline, tol.metric);
    const auto cur = mean(summary, tol.metric);
    if (!base) {
      out.push_back({tol.metric, 0, cur.value_or(0), 0, "missing from the baseline"});
      continue;
    }
    if (!cur) {
      out.push_back({tol.metric, *base, 0, 0, "missing from the current run"});
      continue;
    }
    const double slack = std::max(tol.abs, tol.rel * std::abs(*base));
    const double allowed = tol.higher_is_better ? *base - slack : *base + slack;
    const bool worse = tol.higher_is_better ? *cur < allowed : *cur > allowed;
    if (worse) out.push_back({tol.metric, *base, *cur, allowed, ""});
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
