#include "slamprep/eval/bench/suite.hpp"

#include <yaml-cpp/yaml.h>

#include <cassert>
#include <cmath>
#include <cstdio>

#include "slamprep/algo/calibration/calibration_method.hpp"
#include "slamprep/algo/deskew/deskew.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/paths.hpp"
#include "slamprep/eval/pipeline/calibration_run.hpp"
#include "slamprep/sim/drive/config.hpp"
#include "slamprep/sim/drive/scenario.hpp"
#include "slamprep/sim/physics/world.hpp"
#include "slamprep/sim/yaml/yaml_fields.hpp"

namespace slamprep::eval {
namespace {

using sim::Bounds;
using sim::YamlDoc;

// A million trials is beyond any machine this runs on: such a count is a typo.
constexpr int kMaxSeeds = 100000;
// Trials of one suite (worlds x scenarios x sweep points x seeds): each simulates for seconds at
// least, and 10^9 used to end in bad_alloc after half a minute of expanding them.
constexpr double kMaxTrials = 100000;

void parseSweep(const YamlDoc& doc, const YAML::Node& node, Suite& suite) {
  doc.requireMap(node, "sweep");
  for (const auto& entry : node) {
    const std::string key = doc.keyName(entry.first, "sweep");
    SweepAxis axis{key, doc.stringList(entry.second, "sweep." + key)};
    if (axis.values.empty()) doc.fail(entry.second, "sweep." + key, "is empty");
    suite.sweep.push_back(axis);
  }
}

bool parseBetter(const YamlDoc& doc, const YAML::Node& node, const std::string& key) {
  const std::string value = doc.string(node, key + ".better");
  if (value != "higher" && value != "lower")
    doc.fail(node, key + ".better", "must be higher or lower");
  return value == "higher";
}

void parseTolerances(const YamlDoc& doc, const YAML::Node& node, Suite& suite) {
  doc.requireMap(node, "tolerances");
  const Bounds non_negative{0.0};
  for (const auto& entry : node) {
    const std::string metric = doc.keyName(entry.first, "tolerances");
    const std::string key = "tolerances." + metric;
    doc.requireMap(entry.second, key);
    doc.checkKeys(entry.second, key, {"abs", "rel", "better"});
    Tolerance tol{metric};
    tol.abs = doc.optionalNumber(entry.second, "abs", key, tol.abs, non_negative);
    tol.rel = doc.optionalNumber(entry.second, "rel", key, tol.rel, non_negative);
    if (const YAML::Node better = entry.second["better"])
      tol.higher_is_better = parseBetter(doc, better, key);
    suite.tolerances.push_back(tol);
  }
}

// Only the interval methods: the bench drives no UMBmark square runs.
std::vector<algo::CalibrationMethod> parseCalibrationMethods(const YamlDoc& doc,
                                                             const YAML::Node& node) {
  const std::string key = "calibration_methods";
  std::vector<algo::CalibrationMethod> methods;
  for (const std::string& name : doc.stringList(node, key)) {
    const auto method = algo::parseCalibrationMethod(name);
    if (!method || !algo::isIntervalMethod(*method)) {
      std::vector<std::string> valid;
      for (const auto m : algo::intervalMethods())
        valid.emplace_back(algo::calibrationMethodName(m));
      doc.fail(node, key, unknownNameMessage("method", name, valid));
    }
    methods.push_back(*method);
  }
  return methods;
}

// Why `name` cannot be the results folder results/<name>/ (one file-name part), or "".
std::string badSuiteName(const std::string& name) {
  if (name.empty() || name == "." || name == "..")
    return "must name one folder under --results (not empty, '.' or '..')";
  if (name.size() > 255) return "is longer than 255 bytes (it names a folder)";
  for (unsigned char c : name)
    if (c == '/' || c < 0x20 || c == 0x7f)
      return "must be one file-name part: no '/' or control characters (it names the folder "
             "results/<name>/)";
  return "";
}

std::string suiteName(const YamlDoc& doc, const YAML::Node& node) {
  std::string name = doc.string(node, "name");
  if (const std::string why = badSuiteName(name); !why.empty()) doc.fail(node, "name", why);
  return name;
}

void parseKey(const YamlDoc& doc, const std::string& key, const YAML::Node& value, Suite& suite) {
  if (key == "name")
    suite.name = suiteName(doc, value);
  else if (key == "description")
    suite.description = doc.string(value, key);
  else if (key == "worlds")
    suite.worlds = doc.stringList(value, key);
  else if (key == "scenarios")
    suite.scenarios = doc.stringList(value, key);
  else if (key == "seeds")
    suite.seeds = static_cast<int>(doc.integer(value, key, 1, kMaxSeeds));
  else if (key == "base_seed")
    suite.base_seed = static_cast<std::uint64_t>(doc.integer(value, key, 0, std::int64_t{1} << 53));
  else if (key == "duration_s")  // 0: the scenario's own duration; at most the simulator's day
    suite.duration_s = doc.number(value, key, Bounds{0.0, 86400.0});
  else if (key == "mode")
    suite.mode = doc.string(value, key);
  else if (key == "motion")
    suite.motion = doc.string(value, key);
  else if (key == "calibration_methods")
    suite.calibration_methods = parseCalibrationMethods(doc, value);
  else if (key == "calibration_sideslip")
    suite.calibration_sideslip = doc.boolean(value, key);
  else if (key == "calibration_loop_closure")
    suite.calibration_loop_closure = doc.boolean(value, key);
  else if (key == "deskew_methods")
    suite.deskew_methods = doc.stringList(value, key);
  else if (key == "deskew_geometry")
    suite.deskew_geometry = doc.string(value, key);
  else if (key == "sweep")
    parseSweep(doc, value, suite);
  else if (key == "tolerances")
    parseTolerances(doc, value, suite);
  else if (key == "set") {
    doc.requireMap(value, key);
    for (const auto& e : value) {
      const std::string name = doc.keyName(e.first, key);
      suite.set[name] = doc.string(e.second, key + "." + name);
    }
  } else {
    assert(false && "parseKey: a key checkKeys allows is not handled");
  }
}

void validate(const Suite& suite) {
  const std::string f = suite.source.string();
  if (const std::string why = badSuiteName(suite.name); !why.empty())  // a name from the file's
    throw InputError(f + ": name", why);                               // stem ("..yaml")
  if (suite.worlds.empty()) throw InputError(f + ": worlds", "at least one world is needed");
  if (suite.scenarios.empty()) throw InputError(f + ": scenarios", "at least one scenario");
  if (suite.seeds < 1 || suite.seeds > kMaxSeeds)
    throw InputError(f + ": seeds", "must be between 1 and " + std::to_string(kMaxSeeds));
  if (!std::isfinite(suite.duration_s) || suite.duration_s < 0)
    throw InputError(f + ": duration_s", "must be a finite number, not negative");
  parseName(sim::kSimModeNames, suite.mode, "mode", f + ": mode");
  if (suite.deskew_geometry != "nominal" && suite.deskew_geometry != "true" &&
      suite.deskew_geometry != "calibrated")
    throw InputError(f + ": deskew_geometry",
                     "must be nominal, true or calibrated, not '" + suite.deskew_geometry + "'");
  // The bench drives no scan-to-map matching: icp or groundtruth.
  const auto motion = findName(kMotionSourceNames, suite.motion);
  if (!motion || *motion == MotionSource::kMap)
    throw InputError(f + ": motion",
                     unknownNameMessage("motion", suite.motion, {"icp", "groundtruth"}));
  // Counted in floating point: the product of the sweep axes may not fit any integer.
  double trials = static_cast<double>(suite.worlds.size()) * suite.scenarios.size() * suite.seeds;
  for (const auto& axis : suite.sweep) trials *= static_cast<double>(axis.values.size());
  if (trials > kMaxTrials) {
    char count[64];
    std::snprintf(count, sizeof count, "%.0f", trials);
    throw InputError(f + ": " + (suite.sweep.empty() ? "seeds" : "sweep"),
                     std::string("worlds x scenarios x sweep points x seeds is ") + count +
                         " trials, more than the limit of " +
                         std::to_string(static_cast<int>(kMaxTrials)));
  }
}

// Method names and simulator keys are checked now, not hours into a sweep.
void validateNames(const Suite& suite) {
  const std::string f = suite.source.string();
  for (const auto& m : suite.deskew_methods)
    parseName(algo::kDeskewMethodNames, m, "method", f + ": deskew_methods");
  std::vector<std::pair<std::string, std::string>> assignments(suite.set.begin(), suite.set.end());
  for (const auto& axis : suite.sweep)
    for (const auto& v : axis.values) assignments.emplace_back(axis.key, v);
  for (const auto& [key, value] : assignments) {
    sim::SimConfig config;
    try {
      sim::applyOverride(config, key + "=" + value);
    } catch (const InputError& e) {
      throw InputError(f + ": " + key, e.what());
    }
  }
}

// File-name safe form of a sweep value.
std::string sanitize(const std::string& s) {
  std::string out;
  for (char c : s)
    out += (std::isalnum(static_cast<unsigned char>(c)) || c == '.' || c == '-') ? c : '_';
  return out;
}

}  // namespace

Suite loadSuite(const std::filesystem::path& file) {
  const YamlDoc doc(file.string());
  const YAML::Node root = sim::loadYamlFile(file, doc, "suite file");
  if (!root.IsMap()) throw InputError(file.string(), "a suite must be a YAML map");
  Suite suite;
  suite.source = file;
  suite.name = file.stem().string();
  doc.guard([&] {
    doc.checkKeys(
        root, "",
        {"name", "description", "worlds", "scenarios", "seeds", "base_seed", "duration_s", "mode",
         "motion", "calibration_methods", "calibration_sideslip", "calibration_loop_closure",
         "deskew_methods", "deskew_geometry", "sweep", "tolerances", "set"});
    for (const auto& entry : root) parseKey(doc, doc.keyName(entry.first, ""), entry.second, suite);
  });
  validate(suite);
  validateNames(suite);
  return suite;
}

std::filesystem::path findSuite(const std::string& name_or_path,
                                const std::filesystem::path& suites_dir) {
  const std::filesystem::path direct(name_or_path);
  if (direct.has_extension() || direct.has_parent_path()) {
    if (!std::filesystem::exists(direct)) throw InputError(name_or_path, "no such suite file");
    return direct;
  }
  const auto file = suites_dir / (name_or_path + ".yaml");
  if (!std::filesystem::exists(file))
    throw InputError("--suite " + name_or_path, "no suite " + file.string());
  return file;
}

nlohmann::json suiteSettings(const Suite& suite) {
  nlohmann::json methods = nlohmann::json::array();
  for (const auto method : suite.calibration_methods)
    methods.push_back(std::string(algo::calibrationMethodName(method)));
  return {{"mode", suite.mode},
          {"motion", suite.motion},
          {"calibration_methods", methods},
          {"calibration_sideslip", suite.calibration_sideslip},
          {"calibration_loop_closure", suite.calibration_loop_closure},
          {"deskew_methods", suite.deskew_methods},
          {"deskew_geometry", suite.deskew_geometry}};
}

void attachInputDigests(std::vector<TrialSpec>& trials) {
  std::map<std::string, std::string> digests;  // path as written -> digest
  const auto digest = [&digests](const std::string& file) {
    const auto [it, inserted] = digests.emplace(file, "unreadable");
    if (inserted) try {
        std::uint64_t h = 1469598103934665603ull;  // FNV-1a, as binaryFingerprint
        for (unsigned char c : readFile(resolveDataPath(file))) h = (h ^ c) * 1099511628211ull;
        char hex[17];
        std::snprintf(hex, sizeof hex, "%016llx", static_cast<unsigned long long>(h));
        it->second = hex;
      } catch (const InputError&) {  // the trial itself reports the missing file
      }
    return it->second;
  };
  for (TrialSpec& t : trials)
    t.inputs = {{"world", digest(t.world)}, {"scenario", digest(t.scenario)}};
}

void checkSuiteFiles(const Suite& suite) {
  const auto check = [&suite](const std::vector<std::string>& files, const std::string& key,
                              const auto& load) {
    for (std::size_t i = 0; i < files.size(); ++i) try {
        load(resolveDataPath(files[i]));
      } catch (const InputError& e) {
        throw InputError(suite.source.string() + ": " + key + "[" + std::to_string(i) + "]",
                         e.what());
      }
  };
  check(suite.worlds, "worlds", [](const std::filesystem::path& f) { sim::loadWorld(f); });
  check(suite.scenarios, "scenarios", [](const std::filesystem::path& f) { sim::loadScenario(f); });
}

std::vector<TrialSpec> expandTrials(const Suite& suite) {
  const nlohmann::json settings = suiteSettings(suite);
  // Sweep points: the cartesian product of all axes, last axis varying fastest.
  std::vector<std::map<std::string, std::string>> points{{}};
  for (const auto& axis : suite.sweep) {
    std::vector<std::map<std::string, std::string>> next;
    for (const auto& point : points)
      for (const auto& value : axis.values) {
        auto p = point;
        p[axis.key] = value;
        next.push_back(p);
      }
    points = std::move(next);
  }
  std::vector<TrialSpec> trials;
  for (const auto& world : suite.worlds)
    for (const auto& scenario : suite.scenarios)
      for (const auto& point : points)
        for (int s = 0; s < suite.seeds; ++s) {
          TrialSpec t;
          t.index = trials.size();
          t.world = world;
          t.scenario = scenario;
          t.overrides = suite.set;
          for (const auto& [k, v] : point) t.overrides[k] = v;
          t.sweep = point;
          t.seed = suite.base_seed + static_cast<std::uint64_t>(s);
          t.duration_s = suite.duration_s;
          t.settings = settings;
          char prefix[16];
          std::snprintf(prefix, sizeof prefix, "%04zu", t.index);
          t.id = std::string(prefix) + "-" + std::filesystem::path(world).stem().string() + "-" +
                 std::filesystem::path(scenario).stem().string();
          // Appended piecewise: GCC 12 warns falsely (-Wrestrict) on "-" + std::string here.
          for (const auto& [k, v] : point)
            t.id.append("-").append(sanitize(k)).append("=").append(sanitize(v));
          t.id += "-s" + std::to_string(t.seed);
          trials.push_back(t);
        }
  return trials;
}

}  // namespace slamprep::eval
