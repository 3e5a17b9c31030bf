#include "slamprep/eval/formats/export.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <nlohmann/json.hpp>
#include <numbers>

#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/eval/formats/scan_jsonl.hpp"
#include "slamprep/eval/formats/text_io.hpp"
#include "slamprep/eval/formats/tum.hpp"
#include "slamprep/eval/formats/wheel_odometry.hpp"

namespace slamprep::eval {
namespace fs = std::filesystem;
namespace {

/// The twist at time t from the step that contains it (zero outside the series).
Eigen::Vector3d twistAtTime(const PoseSeries& poses, double t) {
  const auto b = poses.bracket(t);
  if (!b || poses.size() < 2) return Eigen::Vector3d::Zero();
  return twistAt(poses, b->index + 1);
}

void requireScans(const std::vector<ScanRecord>& scans, const std::string& what) {
  if (scans.empty()) throw InputError(what, "no scans to export");
}

std::string appendSe2Line(const SE2& T) {
  const double c = std::cos(T.yaw), s = std::sin(T.yaw);
  const double v[12] = {c, -s, 0, T.x, s, c, 0, T.y, 0, 0, 1, 0};
  std::string line;
  for (int i = 0; i < 12; ++i) {
    if (i) line += ' ';
    slamprep::eval::appendDouble(line, v[i] == 0.0 ? 0.0 : v[i]);  // no "-0.0" in KITTI files
  }
  return line + "\n";
}

const std::vector<ScanRecord>& chosenScans(const ExportInput& input, const ExportParams& params) {
  if (params.scans == "scans") return input.dataset.scans;
  const auto it = input.deskewed.find(params.scans);
  if (it == input.deskewed.end())
    throw InputError("--scans", "the dataset has no deskewed_" + params.scans + ".jsonl");
  return it->second;
}

}  // namespace

ExportFormat parseExportFormat(const std::string& name, const std::string& where) {
  return parseName(kExportFormatNames, name, "format", where);
}

ExportInput loadExportInput(const fs::path& dataset_dir) {
  ExportInput input;
  input.source = dataset_dir.string();
  input.dataset = readDataset(dataset_dir);
  std::error_code ec;
  std::vector<fs::path> deskewed;
  for (const auto& entry : fs::directory_iterator(dataset_dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.starts_with("deskewed_") && name.ends_with(".jsonl")) deskewed.push_back(entry.path());
  }
  std::sort(deskewed.begin(), deskewed.end());  // directory order is not deterministic
  for (const fs::path& file : deskewed) {
    const std::string name = file.filename().string();
    const std::string method = name.substr(9, name.size() - 9 - 6);
    input.deskewed[method] =
        slamprep::eval::parseScans(slamprep::eval::readTextFile(file), file.string());
  }
  return input;
}

PoseSeries calibratedOdometry(const ExportInput& input) {
  const CalibrationChoice& c = input.calibration.value();
  return calibratedOdometry(input.dataset, input.source, c.geometry, c.derived_with);
}

namespace {

/// One line of a CARMEN log, with what orders it in the log.
struct CarmenLine {
  double stamp_s;
  int order;  // ODOM before a ROBOTLASER1 of the same stamp
  std::string text;
};

/// Appends each value after a space, in the shortest round-trip text.
void appendSpacedDoubles(std::string& s, std::initializer_list<double> values) {
  for (double v : values) {
    s += ' ';
    slamprep::eval::appendDouble(s, v);
  }
}

/// The " hostname logger_timestamp" that ends every CARMEN message line.
void appendCarmenTrailer(std::string& s, const std::string& hostname, double stamp_s) {
  s += ' ' + hostname + ' ';
  slamprep::eval::appendDouble(s, stamp_s);
  s += "\n";
}

/// ODOM x y theta tv rv accel timestamp for pose k of the nominal odometry.
CarmenLine carmenOdomLine(const PoseSeries& odom, std::size_t k, const std::string& hostname) {
  const SE2& T = odom[k].value;
  const Eigen::Vector3d xi = twistAt(odom, k);
  std::string s = "ODOM";
  appendSpacedDoubles(s, {T.x, T.y, T.yaw, xi.x(), xi.z(), 0.0, odom[k].stamp_s});
  appendCarmenTrailer(s, hostname, odom[k].stamp_s);
  return {odom[k].stamp_s, 0, s};
}

/// CARMEN has no "no return": such beams read max_range. An unlimited range_max becomes the
/// longest finite reading of the log plus one metre.
double carmenUnlimitedMaxRange(const std::vector<ScanRecord>& scans) {
  double longest_m = 0.0;
  for (const auto& r : scans)
    for (double v : r.scan.ranges_m)
      if (std::isfinite(v)) longest_m = std::max(longest_m, v);
  return std::floor(longest_m) + 1.0;
}

/// ROBOTLASER1 for one scan taken at the odometry pose T_odom_base.
CarmenLine carmenLaserLine(const LaserScan& scan, const SE2& T_odom_base, const PoseSeries& odom,
                           const SE2& T_base_lidar, double unlimited_max_range,
                           const std::string& hostname) {
  const double max_range = std::isfinite(scan.range_max_m) ? scan.range_max_m : unlimited_max_range;
  // CARMEN angles increase: a clockwise scan is written last beam first.
  const bool reverse = scan.angle_increment_rad < 0;
  const std::size_t n = scan.size();
  const double start = reverse ? scan.beamAngle(n - 1) : scan.angle_min_rad;
  const double resolution = std::abs(scan.angle_increment_rad);
  const SE2 laser = T_odom_base * T_base_lidar;
  const Eigen::Vector3d xi = twistAtTime(odom, scan.stamp_s);
  std::string s = "ROBOTLASER1 0";  // laser_type: 0 (not read by CSM or GMapping)
  appendSpacedDoubles(s, {start, resolution * double(n - 1), resolution, max_range, 0.0});
  s += " 0 " + std::to_string(n);  // remission_mode, num_readings
  for (std::size_t i = 0; i < n; ++i) {
    const double r = scan.ranges_m[reverse ? n - 1 - i : i];
    appendSpacedDoubles(s, {std::isfinite(r) ? r : max_range});
  }
  s += " 0";  // num_remissions
  appendSpacedDoubles(s, {laser.x, laser.y, laser.yaw, T_odom_base.x, T_odom_base.y,
                          T_odom_base.yaw, xi.x(), xi.z(), 0.0, 0.0, 0.0, scan.stamp_s});
  appendCarmenTrailer(s, hostname, scan.stamp_s);
  return {scan.stamp_s, 1, s};
}

/// The comment lines naming the fields of every message type the log holds.
std::string carmenHeader() {
  return "# CARMEN log written by slamprep (docs/export.md)\n"
         "# ODOM x y theta tv rv accel timestamp hostname logger_timestamp\n"
         "# ROBOTLASER1 laser_type start_angle field_of_view angular_resolution maximum_range "
         "accuracy remission_mode num_readings [range_readings] num_remissions [remissions] "
         "laser_pose_x laser_pose_y laser_pose_theta robot_pose_x robot_pose_y robot_pose_theta "
         "laser_tv laser_rv forward_safety_dist side_safety_dist turn_axis timestamp hostname "
         "logger_timestamp\n";
}

/// Standard CARMEN parameter, then slamprep's own (other readers skip unknown PARAM names):
/// what `slamprep import --format carmen` needs to rebuild the dataset exactly.
std::string carmenParams(const DatasetInfo& info, const std::vector<ScanRecord>& scans,
                         const std::string& hostname) {
  std::string out;
  auto param = [&](const char* name, double value) {
    out += std::string("PARAM ") + name + ' ';
    slamprep::eval::appendDouble(out, value);
    out += ' ' + hostname + " 0\n";
  };
  param("robot_frontlaser_offset", info.T_base_lidar.x);
  param("robot_frontlaser_side_offset", info.T_base_lidar.y);
  param("robot_frontlaser_angular_offset", info.T_base_lidar.yaw);
  param("slamprep_nominal_r_L", info.nominal_geometry.radius_left_m);
  param("slamprep_nominal_r_R", info.nominal_geometry.radius_right_m);
  param("slamprep_nominal_b", info.nominal_geometry.wheel_base_m);
  if (!scans.empty()) {
    param("slamprep_time_increment", std::abs(scans.front().scan.time_increment_s));
    param("slamprep_scan_time", scans.front().scan.scan_time_s);
  }
  return out;
}

}  // namespace

std::string formatCarmen(const Dataset& d, const std::vector<ScanRecord>& scans,
                         const ExportParams& p, std::size_t* skipped_scans) {
  std::vector<CarmenLine> lines;
  const PoseSeries& odom = d.odom_nominal;
  for (std::size_t k = 0; k < odom.size(); ++k)
    lines.push_back(carmenOdomLine(odom, k, p.carmen_hostname));
  const double unlimited_max_range = carmenUnlimitedMaxRange(scans);
  std::size_t skipped = 0;
  for (const auto& record : scans) {
    const auto T_odom_base = odom.at(record.scan.stamp_s);
    if (!T_odom_base || record.scan.size() == 0) {
      ++skipped;
      continue;
    }
    lines.push_back(carmenLaserLine(record.scan, *T_odom_base, odom, d.info.T_base_lidar,
                                    unlimited_max_range, p.carmen_hostname));
  }
  std::stable_sort(lines.begin(), lines.end(), [](const CarmenLine& a, const CarmenLine& b) {
    return a.stamp_s != b.stamp_s ? a.stamp_s < b.stamp_s : a.order < b.order;
  });
  std::string out = carmenHeader() + carmenParams(d.info, scans, p.carmen_hostname);
  for (const CarmenLine& l : lines) out += l.text;
  if (skipped_scans) *skipped_scans = skipped;
  return out;
}

namespace {

/// One CSM ray: its angle, its reading (NaN: null) and CSM's valid flag.
struct CsmRay {
  double theta = 0.0;
  double reading = std::numeric_limits<double>::quiet_NaN();
  bool valid = false;
};

/// The exact angle of point p, unwrapped next to the beam angle: beam + offset, |offset| <= pi.
double offsetFromBeam(const Eigen::Vector2d& p, double beam_angle) {
  return std::remainder(std::atan2(p.y(), p.x()) - beam_angle, 2.0 * std::numbers::pi);
}

/// The scan's rays: on its grid, or, for a de-skewed scan (p_ref), each corrected point's exact
/// angle and range (a ray without a return keeps the offset of the ray before it). Sorted so that
/// theta increases (clockwise scans reversed) and cut to one turn: CSM requires min_theta =
/// theta[0], max_theta = theta[n-1] and max_theta - min_theta <= 2 pi.
std::vector<CsmRay> csmRays(const ScanRecord& record) {
  const LaserScan& s = record.scan;
  const std::size_t n = s.size();
  std::vector<CsmRay> rays(n);
  const bool exact = record.p_ref.size() == n;
  double offset = 0.0;
  for (std::size_t i = 0; exact && i < n; ++i)
    if (record.p_ref[i]) {
      offset = offsetFromBeam(*record.p_ref[i], s.beamAngle(i));  // for rays before the first
      break;
    }
  for (std::size_t i = 0; i < n; ++i) {
    if (exact) {
      const auto& p = record.p_ref[i];
      if (p) offset = offsetFromBeam(*p, s.beamAngle(i));
      rays[i] = {s.beamAngle(i) + offset, p ? p->norm() : std::numeric_limits<double>::quiet_NaN(),
                 p.has_value()};
    } else {
      const double r = s.ranges_m[i];
      rays[i] = {s.beamAngle(i), std::isfinite(r) ? r : std::numeric_limits<double>::quiet_NaN(),
                 s.valid(i)};
    }
  }
  std::stable_sort(rays.begin(), rays.end(),
                   [](const CsmRay& a, const CsmRay& b) { return a.theta < b.theta; });
  while (rays.size() > 1 && rays.back().theta - rays.front().theta > 2.0 * std::numbers::pi)
    rays.pop_back();  // overlaps the start of the turn
  return rays;
}

}  // namespace

std::string formatCsm(const std::vector<ScanRecord>& scans) {
  std::string out;
  for (const auto& record : scans) {
    const LaserScan& s = record.scan;
    const std::vector<CsmRay> rays = csmRays(record);
    const std::size_t n = rays.size();
    nlohmann::json j;
    j["nrays"] = n;
    j["min_theta"] = n ? rays.front().theta : s.angle_min_rad;
    j["max_theta"] = n ? rays.back().theta : s.angle_min_rad;
    nlohmann::json readings = nlohmann::json::array(), valid = nlohmann::json::array(),
                   theta = nlohmann::json::array();
    for (const CsmRay& ray : rays) {
      readings.push_back(std::isnan(ray.reading) ? nlohmann::json(nullptr)
                                                 : nlohmann::json(ray.reading));
      valid.push_back(ray.valid ? 1 : 0);
      theta.push_back(ray.theta);
    }
    j["readings"] = readings;
    j["valid"] = valid;
    j["theta"] = theta;
    const double sec = std::floor(s.stamp_s);
    const double usec = std::round((s.stamp_s - sec) * 1e6);
    j["timestamp"] = {static_cast<std::int64_t>(sec) + (usec >= 1e6 ? 1 : 0),
                      static_cast<std::int64_t>(usec >= 1e6 ? 0 : usec)};
    auto pose = [](const std::optional<SE2>& T) {
      return T ? nlohmann::json::array({T->x, T->y, T->yaw}) : nlohmann::json(nullptr);
    };
    j["odometry"] = pose(record.T_odom_base_nominal);
    j["true_pose"] = pose(record.T_world_base_true);
    out += j.dump() + "\n";
  }
  return out;
}

std::string sm2CommandLine(const fs::path& csm_file, const SE2& T_base_lidar) {
  std::string line = "CSM's sm2 matches in the lidar frame and needs the mount: sm2 -in " +
                     csm_file.string() + " -laser_x ";
  appendDouble(line, T_base_lidar.x);
  line += " -laser_y ";
  appendDouble(line, T_base_lidar.y);
  line += " -laser_theta ";
  appendDouble(line, T_base_lidar.yaw);
  return line;
}

std::string formatKittiPoses(const std::vector<SE2>& poses) {
  std::string out;
  for (const SE2& T : poses) out += appendSe2Line(T);
  return out;
}

namespace {

/// Writes one output file atomically and lists it in the result.
void writeExportFile(ExportResult& result, const fs::path& file, const std::string& text) {
  writeFileAtomic(file, text);
  result.files.push_back(file);
}

void exportMcap(const ExportInput& input, const fs::path& out, const ExportParams& params,
                ExportResult& result) {
  const Dataset& d = input.dataset;
  if (d.scans.empty()) throw InputError(out.string(), "the dataset has no scans to export");
  writeMcapFile(out, input, params, &result.counts);
  result.files.push_back(out);
  if (!d.hasTruth()) result.notes.push_back("no ground truth: /ground_truth not written");
}

void exportCarmen(const ExportInput& input, const fs::path& out, const ExportParams& params,
                  ExportResult& result) {
  const Dataset& d = input.dataset;
  const auto& scans = chosenScans(input, params);
  requireScans(scans, params.scans);
  std::size_t skipped = 0;
  writeExportFile(result, out, formatCarmen(d, scans, params, &skipped));
  result.counts["ODOM"] = d.odom_nominal.size();
  result.counts["ROBOTLASER1"] = scans.size() - skipped;
  if (skipped)
    result.notes.push_back(std::to_string(skipped) +
                           " scans outside the odometry (or empty) were left out");
}

void exportCsm(const ExportInput& input, const fs::path& out, const ExportParams& params,
               ExportResult& result) {
  const auto& scans = chosenScans(input, params);
  requireScans(scans, params.scans);
  writeExportFile(result, out, formatCsm(scans));
  result.counts["laser_data"] = scans.size();
  result.notes.push_back(sm2CommandLine(out, input.dataset.info.T_base_lidar));
}

void exportTum(const ExportInput& input, const fs::path& out, ExportResult& result) {
  const Dataset& d = input.dataset;
  // Odometry is anchored at the true start pose (when there is truth) so that evo compares
  // it with the ground truth without alignment; the calibrated odometry shares the frame.
  const std::optional<SE2> T_world_odom =
      d.hasTruth() ? anchorOnTruth(d.odom_nominal, d.groundtruth) : std::nullopt;
  auto anchored = [&](const PoseSeries& poses) {
    return T_world_odom ? inWorld(poses, *T_world_odom) : poses;
  };
  if (d.hasTruth()) {
    writeExportFile(result, out / "groundtruth.tum",
                    slamprep::eval::formatTum(d.groundtruth, "groundtruth.tum"));
    result.counts["groundtruth"] = d.groundtruth.size();
  }
  writeExportFile(result, out / "odom_nominal.tum",
                  slamprep::eval::formatTum(anchored(d.odom_nominal), "odom_nominal.tum"));
  result.counts["odom_nominal"] = d.odom_nominal.size();
  if (input.calibration) {
    const PoseSeries cal = calibratedOdometry(input);
    writeExportFile(result, out / "odom_calibrated.tum",
                    slamprep::eval::formatTum(anchored(cal), "odom_calibrated.tum"));
    result.counts["odom_calibrated"] = cal.size();
  }
}

using NamedTrajectories = std::vector<std::pair<std::string, PoseSeries>>;

/// The scan stamps at which every trajectory is defined.
std::vector<double> stampsCoveredByAll(const std::vector<ScanRecord>& scans,
                                       const NamedTrajectories& trajectories) {
  std::vector<double> times;
  for (const auto& r : scans) {
    bool all = true;
    for (const auto& [name, poses] : trajectories) all = all && poses.covers(r.scan.stamp_s);
    if (all) times.push_back(r.scan.stamp_s);
  }
  return times;
}

void exportKitti(const ExportInput& input, const fs::path& out, ExportResult& result) {
  const Dataset& d = input.dataset;
  // KITTI files have no stamps and pair poses by line: every trajectory is sampled at the
  // scan stamps where all of them are defined, each relative to its own first pose.
  NamedTrajectories trajectories;
  if (d.hasTruth()) trajectories.emplace_back("groundtruth", d.groundtruth);
  trajectories.emplace_back("odom_nominal", d.odom_nominal);
  if (input.calibration) trajectories.emplace_back("odom_calibrated", calibratedOdometry(input));
  const std::vector<double> times = stampsCoveredByAll(d.scans, trajectories);
  if (times.empty()) throw InputError(out.string(), "no scan stamp is covered by every trajectory");
  std::string times_text;
  for (double t : times) {
    slamprep::eval::appendDouble(times_text, t);
    times_text += '\n';
  }
  for (const auto& [name, poses] : trajectories) {
    const SE2 first_inv = poses.at(times.front())->inverse();
    std::vector<SE2> rel;
    for (double t : times) rel.push_back(first_inv * *poses.at(t));
    writeExportFile(result, out / (name + ".txt"), formatKittiPoses(rel));
    result.counts[name] = rel.size();
  }
  writeExportFile(result, out / "times.txt", times_text);
}

}  // namespace

ExportResult exportDataset(const ExportInput& input, ExportFormat format, const fs::path& out,
                           const ExportParams& params) {
  ExportResult result;
  result.notes = input.notes;
  if (!input.calibration && input.notes.empty() &&
      (format == ExportFormat::kMcap || format == ExportFormat::kTum ||
       format == ExportFormat::kKitti))
    result.notes.push_back("no calibration JSON: calibrated odometry not written");
  switch (format) {
    case ExportFormat::kMcap:
      exportMcap(input, out, params, result);
      break;
    case ExportFormat::kCarmen:
      exportCarmen(input, out, params, result);
      break;
    case ExportFormat::kCsm:
      exportCsm(input, out, params, result);
      break;
    case ExportFormat::kTum:
      exportTum(input, out, result);
      break;
    case ExportFormat::kKitti:
      exportKitti(input, out, result);
      break;
  }
  result.ok = true;
  return result;
}

}  // namespace slamprep::eval
