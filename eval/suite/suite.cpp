#include "eval/suite/suite.hpp"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstdio>
#include <set>

#include "algo/deskew/deskew.hpp"
#include "core/error.hpp"
#include "sim/drive/config.hpp"

namespace slamprep::eval {
namespace {

// "file:line: key" for an error at a YAML node.
std::string where(const std::filesystem::path& file, const YAML::Node& node,
                  const std::string& key) {
  const int line = node.Mark().line >= 0 ? node.Mark().line + 1 : 0;
  return file.string() + (line > 0 ? ":" + std::to_string(line) : "") + ": " + key;
}

template <typename T>
T as(const std::filesystem::path& file, const YAML::Node& node, const std::string& key) {
  try {
    return node.as<T>();
  } catch (const YAML::Exception&) {
    throw InputError(where(file, node, key), "has the wrong type");
  }
}

std::vector<std::string> stringList(const std::filesystem::path& file, const YAML::Node& node,
                                    const std::string& key) {
  if (node.IsScalar()) return {as<std::string>(file, node, key)};
  if (!node.IsSequence()) throw InputError(where(file, node, key), "must be a list");
  std::vector<std::string> out;
  for (const auto& item : node) out.push_back(as<std::string>(file, item, key));
  return out;
}

void parseSweep(const std::filesystem::path& file, const YAML::Node& node, Suite& suite) {
  if (!node.IsMap()) throw InputError(where(file, node, "sweep"), "must map keys to value lists");
  for (const auto& entry : node) {
    const auto key = as<std::string>(file, entry.first, "sweep");
    SweepAxis axis{key, stringList(file, entry.second, "sweep." + key)};
    if (axis.values.empty())
      throw InputError(where(file, entry.second, "sweep." + key), "is empty");
    suite.sweep.push_back(axis);
  }
}

bool parseBetter(const std::filesystem::path& file, const YAML::Node& node,
                 const std::string& key) {
  const auto value = as<std::string>(file, node, key + ".better");
  if (value != "higher" && value != "lower")
    throw InputError(where(file, node, key + ".better"), "must be higher or lower");
  return value == "higher";
}

void parseTolerances(const std::filesystem::path& file, const YAML::Node& node, Suite& suite) {
  if (!node.IsMap()) throw InputError(where(file, node, "tolerances"), "must be a map");
  for (const auto& entry : node) {
    const auto metric = as<std::string>(file, entry.first, "tolerances");
    const std::string key = "tolerances." + metric;
    Tolerance tol{metric};
    for (const auto& field : entry.second) {
      const auto name = as<std::string>(file, field.first, key);
      if (name == "abs")
        tol.abs = as<double>(file, field.second, key + ".abs");
      else if (name == "rel")
        tol.rel = as<double>(file, field.second, key + ".rel");
      else if (name == "better")
        tol.higher_is_better = parseBetter(file, field.second, key);
      else
        throw InputError(where(file, field.first, key + "." + name),
                         "unknown key (abs, rel, better)");
    }
    if (tol.abs < 0 || tol.rel < 0) throw InputError(where(file, entry.second, key), "negative");
    suite.tolerances.push_back(tol);
  }
}

void parseKey(const std::filesystem::path& file, const std::string& key, const YAML::Node& value,
              Suite& suite) {
  if (key == "name")
    suite.name = as<std::string>(file, value, key);
  else if (key == "description")
    suite.description = as<std::string>(file, value, key);
  else if (key == "worlds")
    suite.worlds = stringList(file, value, key);
  else if (key == "scenarios")
    suite.scenarios = stringList(file, value, key);
  else if (key == "seeds")
    suite.seeds = as<int>(file, value, key);
  else if (key == "base_seed")
    suite.base_seed = as<std::uint64_t>(file, value, key);
  else if (key == "duration_s")
    suite.duration_s = as<double>(file, value, key);
  else if (key == "mode")
    suite.mode = as<std::string>(file, value, key);
  else if (key == "motion")
    suite.motion = as<std::string>(file, value, key);
  else if (key == "calibration_methods")
    suite.calibration_methods = stringList(file, value, key);
  else if (key == "deskew_methods")
    suite.deskew_methods = stringList(file, value, key);
  else if (key == "deskew_geometry")
    suite.deskew_geometry = as<std::string>(file, value, key);
  else if (key == "sweep")
    parseSweep(file, value, suite);
  else if (key == "tolerances")
    parseTolerances(file, value, suite);
  else if (key == "set") {
    if (!value.IsMap()) throw InputError(where(file, value, key), "must map keys to values");
    for (const auto& e : value)
      suite.set[as<std::string>(file, e.first, key)] = as<std::string>(file, e.second, key);
  } else {
    throw InputError(where(file, value, key), "unknown key");
  }
}

void validate(const Suite& suite) {
  const std::string f = suite.source.string();
  if (suite.worlds.empty()) throw InputError(f + ": worlds", "at least one world is needed");
  if (suite.scenarios.empty()) throw InputError(f + ": scenarios", "at least one scenario");
  // A million trials is beyond any machine this runs on: such a count is a typo.
  constexpr int kMaxSeeds = 100000;
  if (suite.seeds < 1 || suite.seeds > kMaxSeeds)
    throw InputError(f + ": seeds", "must be between 1 and " + std::to_string(kMaxSeeds));
  if (!std::isfinite(suite.duration_s) || suite.duration_s < 0)
    throw InputError(f + ": duration_s", "must be a finite number, not negative");
  if (suite.mode != "physics" && suite.mode != "kinematic")
    throw InputError(f + ": mode", "must be physics or kinematic, not '" + suite.mode + "'");
  if (suite.deskew_geometry != "nominal" && suite.deskew_geometry != "true" &&
      suite.deskew_geometry != "calibrated")
    throw InputError(f + ": deskew_geometry",
                     "must be nominal, true or calibrated, not '" + suite.deskew_geometry + "'");
  if (suite.motion != "icp" && suite.motion != "groundtruth")
    throw InputError(f + ": motion", "must be icp or groundtruth, not '" + suite.motion + "'");
}

// Method names and simulator keys are checked now, not hours into a sweep.
void validateNames(const Suite& suite) {
  const std::string f = suite.source.string();
  static const std::set<std::string> kCalibration = {"direct", "model", "joint", "ceres"};
  for (const auto& m : suite.calibration_methods)
    if (!kCalibration.count(m))
      throw InputError(f + ": calibration_methods",
                       "unknown method '" + m + "' (direct, model, joint, ceres)");
  for (const auto& m : suite.deskew_methods)
    if (!algo::parseDeskewMethod(m))
      throw InputError(f + ": deskew_methods", "unknown method '" + m + "'");
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
  YAML::Node root;
  try {
    root = YAML::LoadFile(file.string());
  } catch (const YAML::BadFile&) {
    throw InputError(file.string(), "cannot open suite file");
  } catch (const YAML::ParserException& e) {
    throw InputError(file.string() + ":" + std::to_string(e.mark.line + 1), e.msg);
  }
  if (!root.IsMap()) throw InputError(file.string(), "a suite must be a YAML map");
  Suite suite;
  suite.source = file;
  suite.name = file.stem().string();
  try {
    for (const auto& entry : root)
      parseKey(file, as<std::string>(file, entry.first, "key"), entry.second, suite);
  } catch (const YAML::Exception& e) {  // e.g. a null key: yaml-cpp's InvalidNode
    throw InputError(file.string() + ":" + std::to_string(e.mark.line + 1), e.msg);
  }
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

std::vector<TrialSpec> expandTrials(const Suite& suite) {
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
