#include "slamprep/algo/calibration/interval.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <sstream>

#include "slamprep/core/error.hpp"
#include "slamprep/core/input_file.hpp"
#include "slamprep/core/json_input.hpp"
#include "slamprep/core/odometry.hpp"

namespace slamprep::algo {
namespace {

// Cumulative wheel angles (rad) at time t, linear between the bracketing encoder samples.
Eigen::Vector2d wheelAnglesAt(const EncoderLog& encoders, std::size_t i, double t,
                              double rad_per_tick) {
  const EncoderSample& a = encoders[i];
  const EncoderSample& b = encoders[i + 1];
  const double f = (t - a.stamp_s) / (b.stamp_s - a.stamp_s);
  const double left = a.ticks_left + f * static_cast<double>(b.ticks_left - a.ticks_left);
  const double right = a.ticks_right + f * static_cast<double>(b.ticks_right - a.ticks_right);
  return rad_per_tick * Eigen::Vector2d(left, right);
}

bool isKeyframeGap(const SE2& motion, const IntervalParams& params) {
  if (params.keyframe_translation_m <= 0.0 && params.keyframe_rotation_rad <= 0.0) return true;
  return (params.keyframe_translation_m > 0.0 &&
          motion.translation().norm() >= params.keyframe_translation_m) ||
         (params.keyframe_rotation_rad > 0.0 &&
          std::abs(motion.yaw) >= params.keyframe_rotation_rad);
}

double finiteNumber(const nlohmann::json& j, const std::string& key, const std::string& where) {
  if (!j.contains(key)) throw InputError(where, "missing key \"" + key + "\"");
  const auto& v = j.at(key);
  if (!v.is_number() || !std::isfinite(v.get<double>()))
    throw InputError(where, "\"" + key + "\" must be a finite number");
  return v.get<double>();
}

}  // namespace

double CalibrationInterval::sumLeft_rad() const {
  double sum = 0.0;
  for (const EncoderStep& s : steps) sum += s.dphi_left_rad;
  return sum;
}

double CalibrationInterval::sumRight_rad() const {
  double sum = 0.0;
  for (const EncoderStep& s : steps) sum += s.dphi_right_rad;
  return sum;
}

std::vector<CalibrationInterval> inBaseFrame(std::vector<CalibrationInterval> intervals,
                                             const SE2& T_base_lidar) {
  for (CalibrationInterval& interval : intervals)
    interval.T_lidarStart_lidarEnd =
        T_base_lidar * interval.T_lidarStart_lidarEnd * T_base_lidar.inverse();
  return intervals;
}

SE2 integrateInterval(const CalibrationInterval& interval, const DiffDriveParams& geometry) {
  return integrateSteps(interval.steps, geometry.radius_left_m, geometry.radius_right_m,
                        geometry.wheel_base_m);
}

std::vector<EncoderStep> encoderStepsBetween(const EncoderLog& encoders, int ticks_per_revolution,
                                             double t0_s, double t1_s) {
  std::vector<EncoderStep> steps;
  if (encoders.size() < 2 || !(t1_s > t0_s) || t0_s < encoders.front().stamp_s ||
      t1_s > encoders.back().stamp_s)
    return steps;
  const double rad_per_tick = radiansPerTick(ticks_per_revolution);
  // First sample pair with stamp[i + 1] > t0.
  std::size_t i = std::upper_bound(encoders.begin(), encoders.end(), t0_s,
                                   [](double t, const EncoderSample& s) { return t < s.stamp_s; }) -
                  encoders.begin();
  i = i == 0 ? 0 : i - 1;
  double t = t0_s;
  while (t < t1_s && i + 1 < encoders.size()) {
    const double t_next = std::min(encoders[i + 1].stamp_s, t1_s);
    if (encoders[i + 1].stamp_s > encoders[i].stamp_s && t_next > t) {
      const Eigen::Vector2d d = wheelAnglesAt(encoders, i, t_next, rad_per_tick) -
                                wheelAnglesAt(encoders, i, t, rad_per_tick);
      steps.push_back({t_next - t, d.x(), d.y()});
    }
    t = t_next;
    ++i;
  }
  return steps;
}

IntervalSet buildIntervals(const EncoderLog& encoders, int ticks_per_revolution,
                           const PoseSeries& T_world_lidar, const IntervalParams& params) {
  IntervalSet out;
  std::size_t key = 0;
  for (std::size_t j = 1; j < T_world_lidar.size(); ++j) {
    const auto& a = T_world_lidar[key];
    const auto& b = T_world_lidar[j];
    const SE2 motion = between(a.value, b.value);
    if (!isKeyframeGap(motion, params)) continue;
    CalibrationInterval interval{
        a.stamp_s, b.stamp_s,
        encoderStepsBetween(encoders, ticks_per_revolution, a.stamp_s, b.stamp_s), motion};
    key = j;
    if (interval.steps.empty()) {
      ++out.dropped_uncovered;
    } else if (std::abs(interval.sumLeft_rad()) < params.standstill_wheel_rad &&
               std::abs(interval.sumRight_rad()) < params.standstill_wheel_rad) {
      ++out.dropped_standstill;
    } else {
      out.intervals.push_back(std::move(interval));
    }
  }
  return out;
}

namespace {

// The JSON values of one line, in order: Censi's published lstraight.tuple has two records
// concatenated on its line 1082, so a line may hold several.
std::vector<nlohmann::json> lineValues(const std::string& line, const std::string& where) {
  std::vector<nlohmann::json> values;
  std::istringstream in(line);
  while (!(in >> std::ws).eof()) {
    nlohmann::json j;
    try {
      in >> j;                                      // stops right after one value
    } catch (const nlohmann::json::exception& e) {  // parse_error, and out_of_range for 1e999
      throw InputError(where, std::string("not JSON: ") + e.what());
    }
    values.push_back(std::move(j));
  }
  return values;
}

CalibrationInterval intervalOfRecord(const nlohmann::json& j, const std::string& where, double t) {
  if (!j.is_object()) throw InputError(where, "record must be a JSON object");
  const double duration = finiteNumber(j, "T", where);
  if (duration <= 0.0) throw InputError(where, "\"T\" must be positive");
  const double phi_l = finiteNumber(j, "phi_l", where);
  const double phi_r = finiteNumber(j, "phi_r", where);
  if (!j.contains("sm") || !j["sm"].is_array() || j["sm"].size() != 3)
    throw InputError(where, "\"sm\" must be an array [x, y, th]");
  double sm[3];
  for (int k = 0; k < 3; ++k) {
    if (!j["sm"][k].is_number() || !std::isfinite(j["sm"][k].get<double>()))
      throw InputError(where, "\"sm\" entries must be finite numbers");
    sm[k] = j["sm"][k].get<double>();
  }
  return {t, t + duration, {{duration, phi_l * duration, phi_r * duration}}, {sm[0], sm[1], sm[2]}};
}

}  // namespace

std::vector<CalibrationInterval> readIntervalRecords(std::istream& in, const std::string& source) {
  std::vector<CalibrationInterval> intervals;
  std::string line;
  double t = 0.0;
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    const std::string where = source + ":" + std::to_string(line_no);
    checkJsonStructure(line, source, static_cast<std::size_t>(line_no));  // nesting, repeated keys
    const std::vector<nlohmann::json> records = lineValues(line, where);
    for (std::size_t r = 0; r < records.size(); ++r) {
      const std::string at =
          records.size() > 1 ? where + " record " + std::to_string(r + 1) : where;
      intervals.push_back(intervalOfRecord(records[r], at, t));
      t = intervals.back().t_end_s;
    }
  }
  return intervals;
}

std::vector<CalibrationInterval> readIntervalRecords(const std::filesystem::path& path) {
  // Refused up front: a device (/dev/zero used to fill 2 GB in one line), or over 1 GiB.
  std::istringstream in(readInputFile(path, "record file", kMaxRecordFileBytes));
  return readIntervalRecords(in, path.string());
}

void writeIntervalRecords(std::ostream& out, const std::vector<CalibrationInterval>& intervals) {
  for (const CalibrationInterval& interval : intervals) {
    const SE2& sm = interval.T_lidarStart_lidarEnd;
    const nlohmann::json j = {{"T", interval.duration_s()},
                              {"phi_l", interval.meanRateLeft_radps()},
                              {"phi_r", interval.meanRateRight_radps()},
                              {"sm", {sm.x, sm.y, sm.yaw}}};
    out << j.dump() << "\n";  // nlohmann writes doubles with round-trip precision
  }
}

void writeIntervalRecords(const std::filesystem::path& path,
                          const std::vector<CalibrationInterval>& intervals) {
  std::ofstream out(path);
  if (!out) throw InputError(path.string(), "cannot write");
  writeIntervalRecords(out, intervals);
  if (!out) throw InputError(path.string(), "write failed");
}

}  // namespace slamprep::algo
