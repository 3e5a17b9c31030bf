#include "slamprep/eval/formats/scan_jsonl.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>

#include "slamprep/core/error.hpp"
#include "slamprep/core/json_input.hpp"

namespace slamprep::eval {
namespace {

using nlohmann::json;

[[noreturn]] void fail(const TextLocation& where, const std::string& field,
                       const std::string& what) {
  throw InputError(where.str(), field + ": " + what);
}

// ---- checks shared by writing and reading ---------------------------------------------------

/// What every scan line must satisfy, written or read (so writeDataset never publishes a scan
/// that readDataset refuses): at least one beam, range limits that are distances
/// (0 <= range_min < range_max), and time running forwards (time_increment, scan_time >= 0).
void checkScanHeader(const LaserScan& scan, const TextLocation& where) {
  if (scan.size() == 0) fail(where, "nrays", "an empty scan (0 beams) holds no measurement");
  if (scan.range_min_m < 0.0)
    fail(where, "range_min", "must not be negative (a range is a distance)");
  if (!(scan.range_max_m > scan.range_min_m))
    fail(where, "range_max", "must be greater than range_min");
  if (scan.time_increment_s < 0.0)
    fail(where, "time_increment", "must not be negative (beams are taken in time order)");
  if (scan.scan_time_s < 0.0) fail(where, "scan_time", "must not be negative");
}

// ---- writing ---------------------------------------------------------------------------------

void requireFinite(double value, const TextLocation& where, const char* field) {
  if (!std::isfinite(value)) fail(where, field, "must be finite to be written");
}

void appendKey(std::string& out, const char* key) {
  out += ",\"";
  out += key;
  out += "\":";
}

void appendNumberKey(std::string& out, const char* key, double value) {
  appendKey(out, key);
  appendDouble(out, value);
}

void appendPose(std::string& out, const char* key, const SE2& T, const TextLocation& where) {
  requireFinite(T.x, where, key);
  requireFinite(T.y, where, key);
  requireFinite(T.yaw, where, key);
  appendKey(out, key);
  out += '[';
  appendDouble(out, T.x);
  out += ',';
  appendDouble(out, T.y);
  out += ',';
  appendDouble(out, T.yaw);
  out += ']';
}

// CSM's timestamp: [seconds, microseconds], microseconds rounded.
void appendCsmTimestamp(std::string& out, double stamp_s) {
  double sec = std::floor(stamp_s);
  double usec = std::round((stamp_s - sec) * 1e6);
  if (usec >= 1e6) {
    sec += 1.0;
    usec -= 1e6;
  }
  appendKey(out, "timestamp");
  out += '[';
  appendDouble(out, sec);
  out += ',';
  appendDouble(out, usec);
  out += ']';
}

void appendBeamArrays(std::string& out, const LaserScan& scan) {
  const std::size_t n = scan.size();
  appendKey(out, "readings");
  out += '[';
  for (std::size_t i = 0; i < n; ++i) {
    if (i) out += ',';
    if (std::isfinite(scan.ranges_m[i]))
      appendDouble(out, scan.ranges_m[i]);
    else
      out += "null";
  }
  out += ']';
  appendKey(out, "valid");
  out += '[';
  for (std::size_t i = 0; i < n; ++i) {
    if (i) out += ',';
    out += scan.valid(i) ? '1' : '0';
  }
  out += ']';
  appendKey(out, "theta");
  out += '[';
  for (std::size_t i = 0; i < n; ++i) {
    if (i) out += ',';
    appendDouble(out, scan.beamAngle(i));
  }
  out += ']';
}

void appendPoints(std::string& out, const char* key,
                  const std::vector<std::optional<Eigen::Vector2d>>& points,
                  const TextLocation& where) {
  appendKey(out, key);
  out += '[';
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (i) out += ',';
    if (!points[i]) {
      out += "null";
      continue;
    }
    if (!points[i]->allFinite())
      fail(where, std::string(key) + "[" + std::to_string(i) + "]", "not finite");
    out += '[';
    appendDouble(out, points[i]->x());
    out += ',';
    appendDouble(out, points[i]->y());
    out += ']';
  }
  out += ']';
}

// ---- reading ---------------------------------------------------------------------------------

const json* find(const json& object, const char* key) {
  const auto it = object.find(key);
  return it == object.end() ? nullptr : &*it;
}

double toFinite(const json& value, const TextLocation& where, const std::string& field) {
  if (!value.is_number())
    fail(where, field, "expected a number, got " + std::string(value.type_name()));
  const double x = value.get<double>();
  if (!std::isfinite(x)) fail(where, field, "must be finite");
  return x;
}

double requiredNumber(const json& object, const char* key, const TextLocation& where) {
  const json* value = find(object, key);
  if (!value) fail(where, key, "missing required key");
  return toFinite(*value, where, key);
}

double optionalNumber(const json& object, const char* key, double fallback,
                      const TextLocation& where) {
  const json* value = find(object, key);
  return value ? toFinite(*value, where, key) : fallback;
}

const json& arrayOfSize(const json& object, const char* key, std::size_t size,
                        const TextLocation& where) {
  const json& value = object.at(key);
  if (!value.is_array()) fail(where, key, "expected an array");
  if (value.size() != size)
    fail(where, key,
         "has " + std::to_string(value.size()) + " entries but nrays is " + std::to_string(size));
  return value;
}

// [x, y, th] -> SE2; null, or an array holding null (CSM writes NaN as null), means "unknown".
std::optional<SE2> optionalPose(const json& object, const char* key, const TextLocation& where) {
  const json* value = find(object, key);
  if (!value || value->is_null()) return std::nullopt;  // the CSM export writes null: unknown
  if (!value->is_array() || value->size() != 3) fail(where, key, "expected [x, y, th]");
  for (const auto& v : *value)
    if (v.is_null()) return std::nullopt;
  return SE2(toFinite((*value)[0], where, std::string(key) + "[0]"),
             toFinite((*value)[1], where, std::string(key) + "[1]"),
             toFinite((*value)[2], where, std::string(key) + "[2]"));
}

std::size_t readNrays(const json& object, const TextLocation& where) {
  const json* value = find(object, "nrays");
  if (!value) fail(where, "nrays", "missing required key");
  if (!value->is_number_integer() || value->get<std::int64_t>() < 0)
    fail(where, "nrays", "expected a non-negative integer");
  return value->get<std::size_t>();
}

double readStamp(const json& object, const TextLocation& where) {
  if (find(object, "stamp_s")) return requiredNumber(object, "stamp_s", where);
  const json* ts = find(object, "timestamp");
  if (!ts) fail(where, "stamp_s", "missing required key (and no CSM \"timestamp\")");
  if (!ts->is_array() || ts->size() != 2) fail(where, "timestamp", "expected [sec, usec]");
  return toFinite((*ts)[0], where, "timestamp[0]") +
         1e-6 * toFinite((*ts)[1], where, "timestamp[1]");
}

// angle_min/angle_increment, or CSM's min_theta/max_theta for files without slamprep's fields.
void readAngles(const json& object, std::size_t nrays, LaserScan& scan, const TextLocation& where) {
  if (find(object, "angle_min")) {
    scan.angle_min_rad = requiredNumber(object, "angle_min", where);
    scan.angle_increment_rad = requiredNumber(object, "angle_increment", where);
    return;
  }
  scan.angle_min_rad = requiredNumber(object, "min_theta", where);
  const double max_theta = requiredNumber(object, "max_theta", where);
  scan.angle_increment_rad = nrays > 1 ? (max_theta - scan.angle_min_rad) / (nrays - 1) : 0.0;
}

// A scan sweeps at most one revolution (and a beam) from within one revolution of 0: an increment
// of 0 puts every beam on one ray, 1e300 turns no real way (both used to be read as given).
void checkAngles(const json& object, const LaserScan& scan, const TextLocation& where) {
  const bool csm = !find(object, "angle_min");
  const char* min_key = csm ? "min_theta" : "angle_min";
  const char* increment_key = csm ? "max_theta" : "angle_increment";
  const double turn = 2.0 * std::numbers::pi;
  const double step = std::abs(scan.angle_increment_rad);
  if (std::abs(scan.angle_min_rad) > turn)
    fail(where, min_key, "more than one revolution (2 pi) from 0");
  if (scan.size() > 1 && step == 0.0)
    fail(where, increment_key, "puts all " + std::to_string(scan.size()) + " beams at one angle");
  if (step > turn || step * static_cast<double>(scan.size() - 1) > turn + step * (1.0 + 1e-9))
    fail(where, increment_key,
         "the beams span more than one revolution (2 pi plus one beam) with " +
             std::to_string(scan.size()) + " beams");
}

void readRangeLimits(const json& object, LaserScan& scan, const TextLocation& where) {
  scan.range_min_m = optionalNumber(object, "range_min", 0.0, where);
  const json* max = find(object, "range_max");
  scan.range_max_m = (!max || max->is_null()) ? std::numeric_limits<double>::infinity()
                                              : toFinite(*max, where, "range_max");
}

bool readValidFlag(const json& v, const TextLocation& where, std::size_t i) {
  if (v.is_boolean()) return v.get<bool>();
  if (v.is_number_integer() && (v.get<std::int64_t>() == 0 || v.get<std::int64_t>() == 1))
    return v.get<std::int64_t>() == 1;
  fail(where, "valid[" + std::to_string(i) + "]", "expected 0 or 1");
}

// readings (null = no return = +inf); a beam CSM marks invalid is honoured as +inf when its
// reading would otherwise look valid.
void readRanges(const json& object, std::size_t nrays, LaserScan& scan, const TextLocation& where) {
  if (!find(object, "readings")) fail(where, "readings", "missing required key");
  const json& readings = arrayOfSize(object, "readings", nrays, where);
  const json* valid = find(object, "valid") ? &arrayOfSize(object, "valid", nrays, where) : nullptr;
  const double inf = std::numeric_limits<double>::infinity();
  scan.ranges_m.resize(nrays);
  for (std::size_t i = 0; i < nrays; ++i) {
    const json& r = readings[i];
    scan.ranges_m[i] =
        r.is_null() ? inf : toFinite(r, where, "readings[" + std::to_string(i) + "]");
    if (scan.ranges_m[i] < 0.0)  // a range is a distance; null marks no return
      fail(where, "readings[" + std::to_string(i) + "]", "must not be negative (null: no return)");
    if (!valid) continue;
    const bool flagged_valid = readValidFlag((*valid)[i], where, i);
    if (flagged_valid && r.is_null())
      fail(where, "valid[" + std::to_string(i) + "]", "is 1 but readings[i] is null");
    if (!flagged_valid && scan.valid(i)) scan.ranges_m[i] = inf;
  }
}

std::vector<std::optional<Eigen::Vector2d>> readPoints(const json& object, const char* key,
                                                       std::size_t nrays,
                                                       const TextLocation& where) {
  std::vector<std::optional<Eigen::Vector2d>> points;
  if (!find(object, key)) return points;
  const json& array = arrayOfSize(object, key, nrays, where);
  points.resize(nrays);
  for (std::size_t i = 0; i < nrays; ++i) {
    const json& p = array[i];
    if (p.is_null()) continue;
    const std::string field = std::string(key) + "[" + std::to_string(i) + "]";
    if (!p.is_array() || p.size() != 2) fail(where, field, "expected [x, y] or null");
    points[i] = Eigen::Vector2d(toFinite(p[0], where, field), toFinite(p[1], where, field));
  }
  return points;
}

// CSM's per-ray theta, when it is not the regular grid of min_theta/angle_increment (an exact
// de-skewed export): each ray's point, so that no ray is read at a wrong angle. Empty on the grid
// (to 1e-9 rad) or when theta holds anything but finite numbers (it used to be ignored).
std::vector<std::optional<Eigen::Vector2d>> raysOffGrid(const json& object, const LaserScan& scan,
                                                        const TextLocation& where) {
  std::vector<std::optional<Eigen::Vector2d>> points;
  if (!find(object, "theta")) return points;
  const json& theta = arrayOfSize(object, "theta", scan.size(), where);
  bool on_grid = true;
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!theta[i].is_number() || !std::isfinite(theta[i].get<double>())) return {};
    on_grid = on_grid && std::abs(theta[i].get<double>() - scan.beamAngle(i)) <= 1e-9;
  }
  if (on_grid) return points;
  points.resize(scan.size());
  for (std::size_t i = 0; i < scan.size(); ++i) {
    const double th = theta[i].get<double>();
    if (scan.valid(i)) points[i] = scan.ranges_m[i] * Eigen::Vector2d(std::cos(th), std::sin(th));
  }
  return points;
}

ScanRecord readScanObject(const json& object, const TextLocation& where) {
  ScanRecord record;
  LaserScan& scan = record.scan;
  const std::size_t nrays = readNrays(object, where);
  scan.stamp_s = readStamp(object, where);
  readAngles(object, nrays, scan, where);
  scan.time_increment_s = optionalNumber(object, "time_increment", 0.0, where);
  scan.scan_time_s = optionalNumber(object, "scan_time", 0.0, where);
  readRangeLimits(object, scan, where);
  readRanges(object, nrays, scan, where);
  if (nrays > 0) checkAngles(object, scan, where);
  record.T_odom_base_nominal = optionalPose(object, "odometry", where);
  record.T_world_base_true = optionalPose(object, "true_pose", where);
  record.p_ref_true = readPoints(object, "p_ref_true", nrays, where);
  record.p_ref = find(object, "p_ref") ? readPoints(object, "p_ref", nrays, where)
                                       : raysOffGrid(object, scan, where);
  checkScanHeader(scan, where);
  return record;
}

}  // namespace

void appendScanLine(std::string& out, const ScanRecord& record, const TextLocation& where) {
  const LaserScan& scan = record.scan;
  const std::size_t n = scan.size();
  requireFinite(scan.stamp_s, where, "stamp_s");
  requireFinite(scan.angle_min_rad, where, "angle_min");
  requireFinite(scan.angle_increment_rad, where, "angle_increment");
  requireFinite(scan.time_increment_s, where, "time_increment");
  requireFinite(scan.scan_time_s, where, "scan_time");
  requireFinite(scan.range_min_m, where, "range_min");
  if (std::isnan(scan.range_max_m) || scan.range_max_m == -HUGE_VAL)
    fail(where, "range_max", "must be finite or +inf to be written");
  checkScanHeader(scan, where);
  for (const auto& [key, points] :
       {std::pair{"p_ref_true", &record.p_ref_true}, std::pair{"p_ref", &record.p_ref}})
    if (!points->empty() && points->size() != n)
      fail(
          where, key,
          "has " + std::to_string(points->size()) + " entries for " + std::to_string(n) + " beams");

  out += "{\"nrays\":";
  appendInt(out, static_cast<std::int64_t>(n));
  appendNumberKey(out, "min_theta", n ? scan.beamAngle(0) : scan.angle_min_rad);
  appendNumberKey(out, "max_theta", n ? scan.beamAngle(n - 1) : scan.angle_min_rad);
  appendBeamArrays(out, scan);
  appendCsmTimestamp(out, scan.stamp_s);
  if (record.T_odom_base_nominal) appendPose(out, "odometry", *record.T_odom_base_nominal, where);
  if (record.T_world_base_true) appendPose(out, "true_pose", *record.T_world_base_true, where);
  appendNumberKey(out, "stamp_s", scan.stamp_s);
  appendNumberKey(out, "angle_min", scan.angle_min_rad);
  appendNumberKey(out, "angle_increment", scan.angle_increment_rad);
  appendNumberKey(out, "time_increment", scan.time_increment_s);
  appendNumberKey(out, "scan_time", scan.scan_time_s);
  appendNumberKey(out, "range_min", scan.range_min_m);
  appendKey(out, "range_max");
  if (std::isfinite(scan.range_max_m))
    appendDouble(out, scan.range_max_m);
  else
    out += "null";
  if (!record.p_ref_true.empty()) appendPoints(out, "p_ref_true", record.p_ref_true, where);
  if (!record.p_ref.empty()) appendPoints(out, "p_ref", record.p_ref, where);
  out += "}\n";
}

ScanRecord parseScanLine(std::string_view line, const TextLocation& where) {
  json object;
  checkJsonStructure(line, where.file, where.line);  // nesting and repeated keys
  try {
    object = json::parse(line);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for 1e999
    throw InputError(where.str(), std::string("bad JSON: ") + e.what());
  }
  if (!object.is_object()) throw InputError(where.str(), "expected a JSON object per line");
  try {
    return readScanObject(object, where);
  } catch (const json::exception& e) {  // a type the checks above missed: still a user error
    throw InputError(where.str(), std::string("unexpected JSON content: ") + e.what());
  }
}

std::string formatScans(const std::vector<ScanRecord>& scans, const std::string& file) {
  std::string out;
  if (!scans.empty()) out.reserve(scans.size() * (scans.front().scan.size() * 80 + 512));
  for (std::size_t k = 0; k < scans.size(); ++k) {
    const TextLocation where{file, k + 1};
    if (k > 0)
      requireIncreasing(scans[k - 1].scan.stamp_s, scans[k].scan.stamp_s, where, "stamp_s");
    appendScanLine(out, scans[k], where);
  }
  return out;
}

namespace {

// scans.jsonl a few scans at a time, from `next` (nullptr after the last); stamps must increase.
void writeScanPieces(const std::filesystem::path& path, const std::string& file,
                     const std::function<const ScanRecord*()>& next) {
  std::size_t k = 0;
  double last_stamp = 0.0;
  writeTextFile(path, [&](std::string& out) {
    // About 1 MB per piece: a 720-beam scan is ~60 KB of text.
    for (const std::size_t end = k + 16; k < end; ++k) {
      const ScanRecord* record = next();
      if (!record) break;
      const TextLocation where{file, k + 1};
      if (k > 0) requireIncreasing(last_stamp, record->scan.stamp_s, where, "stamp_s");
      last_stamp = record->scan.stamp_s;
      appendScanLine(out, *record, where);
    }
    return !out.empty();
  });
}

}  // namespace

void writeScans(const std::filesystem::path& path, const std::vector<ScanRecord>& scans,
                const std::string& file) {
  std::size_t i = 0;
  writeScanPieces(path, file, [&] { return i < scans.size() ? &scans[i++] : nullptr; });
}

void writeScans(const std::filesystem::path& path, const ScanSource& next,
                const std::string& file) {
  ScanRecord record;
  writeScanPieces(path, file, [&] { return next(record) ? &record : nullptr; });
}

std::vector<ScanRecord> parseScans(std::string_view text, const std::string& file,
                                   std::vector<std::size_t>* line_numbers) {
  std::vector<ScanRecord> scans;
  if (line_numbers) line_numbers->clear();
  LineCursor cursor(text);
  std::string_view line;
  while (cursor.next(line)) {
    if (trim(line).empty()) continue;
    const TextLocation where{file, cursor.lineNumber()};
    ScanRecord record = parseScanLine(line, where);
    if (!scans.empty())
      requireIncreasing(scans.back().scan.stamp_s, record.scan.stamp_s, where, "stamp_s");
    scans.push_back(std::move(record));
    if (line_numbers) line_numbers->push_back(cursor.lineNumber());
  }
  return scans;
}

}  // namespace slamprep::eval
