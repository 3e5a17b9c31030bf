#include "slamprep/eval/formats/dataset_json.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "slamprep/core/error.hpp"
#include "slamprep/core/json_input.hpp"

namespace slamprep::eval {
namespace {

using nlohmann::json;
using nlohmann::ordered_json;

constexpr int kFormatVersion = 1;

[[noreturn]] void keyError(const std::string& file, const std::string& key,
                           const std::string& what) {
  throw InputError(file, key + ": " + what);
}

// ---- writing ---------------------------------------------------------------------------------

void checkGeometry(const DiffDriveParams& g, const std::string& file, const std::string& key) {
  const std::pair<const char*, double> fields[] = {
      {"r_L", g.radius_left_m}, {"r_R", g.radius_right_m}, {"b", g.wheel_base_m}};
  for (const auto& [name, value] : fields)
    if (!std::isfinite(value) || value <= 0.0)
      keyError(file, key + "." + name, "must be a finite length > 0 to be written");
}

ordered_json geometryJson(const DiffDriveParams& g) {
  return {{"r_L", g.radius_left_m}, {"r_R", g.radius_right_m}, {"b", g.wheel_base_m}};
}

// ---- reading ---------------------------------------------------------------------------------

const json& requiredKey(const json& object, const std::string& prefix, const char* key,
                        const std::string& file) {
  const auto it = object.find(key);
  if (it == object.end()) keyError(file, prefix + key, "missing required key");
  return *it;
}

double finiteNumber(const json& object, const std::string& prefix, const char* key,
                    const std::string& file) {
  const json& value = requiredKey(object, prefix, key, file);
  if (!value.is_number()) keyError(file, prefix + key, "expected a number");
  const double x = value.get<double>();
  if (!std::isfinite(x)) keyError(file, prefix + key, "must be finite");
  return x;
}

double positiveLength(const json& object, const std::string& prefix, const char* key,
                      const std::string& file) {
  const double x = finiteNumber(object, prefix, key, file);
  if (x <= 0.0) keyError(file, prefix + key, "must be > 0 (metres)");
  return x;
}

const json& requiredObject(const json& object, const char* key, const std::string& file) {
  const json& value = requiredKey(object, "", key, file);
  if (!value.is_object()) keyError(file, key, "expected an object");
  return value;
}

std::string requiredString(const json& object, const char* key, const std::string& file) {
  const json& value = requiredKey(object, "", key, file);
  if (!value.is_string()) keyError(file, key, "expected a string");
  return value.get<std::string>();
}

std::int64_t requiredInteger(const json& object, const char* key, const std::string& file) {
  const json& value = requiredKey(object, "", key, file);
  if (!value.is_number_integer()) keyError(file, key, "expected an integer");
  if (value.is_number_unsigned() &&
      value.get<std::uint64_t>() > std::uint64_t(std::numeric_limits<std::int64_t>::max()))
    keyError(file, key, "integer out of range");
  return value.get<std::int64_t>();
}

DiffDriveParams readGeometry(const json& object, const char* key, const std::string& file) {
  const json& g = requiredObject(object, key, file);
  const std::string prefix = std::string(key) + ".";
  DiffDriveParams out;
  out.radius_left_m = positiveLength(g, prefix, "r_L", file);
  out.radius_right_m = positiveLength(g, prefix, "r_R", file);
  out.wheel_base_m = positiveLength(g, prefix, "b", file);
  return out;
}

// 1-based line of a byte offset, for JSON syntax errors.
DatasetInfo readInfo(const json& root, const std::string& file) {
  DatasetInfo info;
  const std::int64_t version = requiredInteger(root, "format_version", file);
  if (version != kFormatVersion)
    keyError(file, "format_version",
             "unsupported version " + std::to_string(version) + " (this build reads 1)");
  info.format_version = kFormatVersion;
  info.world = requiredString(root, "world", file);
  info.scenario = requiredString(root, "scenario", file);
  const json& seed = requiredKey(root, "", "seed", file);
  if (!seed.is_number_unsigned() && !(seed.is_number_integer() && seed.get<std::int64_t>() == 0))
    keyError(file, "seed", "expected a non-negative integer");
  info.seed = seed.get<std::uint64_t>();
  if (root.contains("true")) info.true_geometry = readGeometry(root, "true", file);
  info.nominal_geometry = readGeometry(root, "nominal", file);
  const json& mount = requiredObject(root, "lidar_mount", file);
  info.T_base_lidar = SE2(finiteNumber(mount, "lidar_mount.", "x", file),
                          finiteNumber(mount, "lidar_mount.", "y", file),
                          finiteNumber(mount, "lidar_mount.", "yaw", file));
  if (root.contains("true_lidar_mount")) {
    const json& t = requiredObject(root, "true_lidar_mount", file);
    info.true_T_base_lidar = SE2(finiteNumber(t, "true_lidar_mount.", "x", file),
                                 finiteNumber(t, "true_lidar_mount.", "y", file),
                                 finiteNumber(t, "true_lidar_mount.", "yaw", file));
  }
  const std::int64_t ticks = requiredInteger(root, "ticks_per_revolution", file);
  if (ticks <= 0 || ticks > std::numeric_limits<int>::max())
    keyError(file, "ticks_per_revolution", "must be a positive int, got " + std::to_string(ticks));
  info.ticks_per_revolution = static_cast<int>(ticks);
  info.config = requiredObject(root, "config", file);
  if (root.contains("faults")) info.faults = requiredObject(root, "faults", file);
  return info;
}

}  // namespace

std::string formatDatasetInfo(const DatasetInfo& info, const std::string& file) {
  if (info.format_version != kFormatVersion)
    keyError(file, "format_version", "this build writes version 1 only");
  checkGeometry(info.nominal_geometry, file, "nominal");
  if (info.true_geometry) checkGeometry(*info.true_geometry, file, "true");
  const auto finite = [](const SE2& m) {
    return std::isfinite(m.x) && std::isfinite(m.y) && std::isfinite(m.yaw);
  };
  const SE2& mount = info.T_base_lidar;
  if (!finite(mount)) keyError(file, "lidar_mount", "must be finite to be written");
  if (info.true_T_base_lidar && !finite(*info.true_T_base_lidar))
    keyError(file, "true_lidar_mount", "must be finite to be written");
  if (info.ticks_per_revolution <= 0) keyError(file, "ticks_per_revolution", "must be > 0");
  if (!info.config.is_object()) keyError(file, "config", "must be a JSON object");

  ordered_json out;
  out["format_version"] = kFormatVersion;
  out["world"] = info.world;
  out["scenario"] = info.scenario;
  out["seed"] = info.seed;
  if (info.true_geometry) out["true"] = geometryJson(*info.true_geometry);
  out["nominal"] = geometryJson(info.nominal_geometry);
  out["lidar_mount"] = {{"x", mount.x}, {"y", mount.y}, {"yaw", mount.yaw}};
  if (const auto& t = info.true_T_base_lidar)
    out["true_lidar_mount"] = {{"x", t->x}, {"y", t->y}, {"yaw", t->yaw}};
  out["ticks_per_revolution"] = info.ticks_per_revolution;
  out["config"] = ordered_json(info.config);
  if (!info.faults.is_null()) out["faults"] = ordered_json(info.faults);
  return out.dump(2) + "\n";
}

DatasetInfo parseDatasetInfo(std::string_view text, const std::string& file) {
  const json root = parseJsonInput(text, file);  // nesting and repeated keys checked first
  if (!root.is_object()) throw InputError(file, "expected a JSON object");
  try {
    return readInfo(root, file);
  } catch (const json::exception& e) {  // a type the checks missed: still a user error
    throw InputError(file, std::string("unexpected JSON content: ") + e.what());
  }
}

}  // namespace slamprep::eval
