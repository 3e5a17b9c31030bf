// CARMEN log -> dataset (docs/export.md, "Import"): one laser stream, the odometry from ODOM lines
// or the laser lines' robot poses, the mount from PARAM lines or the user, nothing invented.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <utility>

#include "slamprep/core/error.hpp"
#include "slamprep/core/order_statistics.hpp"
#include "slamprep/eval/formats/carmen.hpp"
#include "slamprep/eval/formats/import.hpp"
#include "slamprep/eval/formats/import_common.hpp"
#include "slamprep/eval/formats/range_limit.hpp"
#include "slamprep/eval/formats/stale_odometry.hpp"
#include "slamprep/eval/formats/text_io.hpp"

namespace slamprep::eval {
namespace {

constexpr double kDegree = std::numbers::pi / 180;

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

std::string poseText(const SE2& T) {
  return "x " + number(T.x) + " m, y " + number(T.y) + " m, yaw " + number(T.yaw / kDegree) +
         " deg";
}

/// A PARAM value of a CARMEN log as a finite number; nullopt when the log has no such PARAM.
std::optional<double> carmenParam(const CarmenLog& log, const std::string& name,
                                  const std::string& file) {
  const auto it = log.params.find(name);
  if (it == log.params.end()) return std::nullopt;
  return parseFiniteDouble(it->second.value, {file, it->second.line}, name);
}

/// The laser stream to import: the one asked for, else the first of ROBOTLASER1, FLASER,
/// RLASER, RAWLASER1..4 the log has (the map is ordered so).
CarmenLaserType chooseLaser(const CarmenLog& log, const std::string& wanted,
                            const std::string& file) {
  if (log.lasers.empty())
    throw InputError(file, "no laser lines (ROBOTLASER1, FLASER, RLASER, RAWLASER1..4)");
  if (wanted.empty()) return log.lasers.begin()->first;
  const auto type = parseCarmenLaserType(wanted);
  if (!type)
    throw InputError("--laser", "unknown message \"" + wanted +
                                    "\" (ROBOTLASER1, FLASER, RLASER, RAWLASER1..4)");
  if (!log.lasers.count(*type)) throw InputError(file, "no " + wanted + " lines (--laser)");
  return *type;
}

/// The odometry: ODOM lines, or the laser lines' robot poses (FLASER odom_x odom_y odom_theta,
/// ROBOTLASER1 robot_pose) when asked or when the log has fewer than 2 ODOM lines.
PoseSeries odometryOf(const CarmenLog& log, const std::vector<CarmenLaser>& lasers,
                      const ImportParams& p, const std::string& file, ImportSummary& s) {
  const std::string name(carmenMessageName(lasers.front().type));
  const bool laser_poses = lasers.front().T_odom_base.has_value();
  const std::string mode = !p.odometry.empty()        ? p.odometry
                           : log.odometry.size() >= 2 ? "odom"
                           : laser_poses              ? "laser"
                                                      : "odom";
  PoseSeries poses;
  if (mode == "odom") {
    if (log.odometry.size() < 2)
      throw InputError(
          file, "fewer than 2 ODOM lines" +
                    (laser_poses ? std::string() : " and the " + name + " lines carry no pose"));
    for (const auto& o : log.odometry) poses.push_back(o.stamp_s, o.T_odom_base);
    s.odometry = std::to_string(log.odometry.size()) + " ODOM lines";
  } else if (mode == "laser") {
    if (!laser_poses) throw InputError(file, "--odometry laser: " + name + " lines carry no pose");
    for (const auto& l : lasers) poses.push_back(l.scan.stamp_s, *l.T_odom_base);
    s.odometry = std::to_string(lasers.size()) + " " + name + " lines' robot poses (" +
                 (name == "ROBOTLASER1" ? "robot_pose" : "odom_x odom_y odom_theta") + ")" +
                 (log.odometry.empty() ? ": the log has no ODOM lines" : "");
    if (!log.odometry.empty())
      s.dropped["ODOM: odometry taken from the laser lines (--odometry laser)"] =
          log.odometry.size();
  } else {
    throw InputError("--odometry", "expected odom or laser, not \"" + p.odometry + "\"");
  }
  return poses;
}

/// The nominal geometry: the given one, else the log's PARAM slamprep_nominal_* lines, else none.
std::optional<DiffDriveParams> nominalGeometry(const CarmenLog& log, const ImportParams& p,
                                               const std::string& file, ImportSummary& s) {
  if (p.nominal_geometry) {
    s.nominal_geometry = "given (--nominal / --wheel-*)";
    return p.nominal_geometry;
  }
  const auto r_L = carmenParam(log, "slamprep_nominal_r_L", file);
  const auto r_R = carmenParam(log, "slamprep_nominal_r_R", file);
  const auto b = carmenParam(log, "slamprep_nominal_b", file);
  if (r_L && r_R && b) {
    const DiffDriveParams g{*r_L, *r_R, *b};
    checkGeometry(g, file + ": PARAM slamprep_nominal_*");
    s.nominal_geometry = "PARAM slamprep_nominal_r_L/_r_R/_b";
    return g;
  }
  s.nominal_geometry =
      "absent (not in the log, no --nominal r_L,r_R,b): a CARMEN log has odometry poses, not "
      "wheel ticks, so no encoders were derived; dataset.json holds a placeholder "
      "(nominal_geometry_from: absent)";
  return std::nullopt;
}

/// The mount the PARAM lines give for this laser; nullopt when they give none.
std::optional<SE2> paramMount(const CarmenLog& log, CarmenLaserType type, const std::string& file,
                              std::string& source) {
  const auto param = [&](const char* name) { return carmenParam(log, name, file); };
  if (type == CarmenLaserType::kFlaser || type == CarmenLaserType::kRobotLaser1) {
    const auto x = param("robot_frontlaser_offset");
    if (!x) return std::nullopt;
    const auto y = param("robot_frontlaser_side_offset");
    const auto yaw = param("robot_frontlaser_angular_offset");
    source = std::string("PARAM robot_frontlaser_offset") + (y ? ", _side_offset" : "") +
             (yaw ? ", _angular_offset" : "");
    return SE2(*x, y.value_or(0.0), yaw.value_or(0.0));
  }
  if (type == CarmenLaserType::kRlaser) {
    const auto x = param("robot_rearlaser_offset");
    if (!x) return std::nullopt;
    // The rear laser looks backwards (GMapping's reading of the same PARAM).
    source = "PARAM robot_rearlaser_offset, turned by 180 deg (rear laser)";
    return SE2(*x, 0.0, std::numbers::pi);
  }
  return std::nullopt;  // RAWLASERn: CARMEN has no mount PARAM for raw lasers
}

/// Largest distance (m) and turn (rad) between `mount` and the lines' robot_pose^-1 laser_pose.
std::pair<double, double> mountDeparture(const std::vector<CarmenLaser>& lasers, const SE2& mount) {
  double dx = 0.0, dyaw = 0.0;
  for (const auto& l : lasers)
    if (l.T_odom_base && l.T_odom_laser) {
      const SE2 e = between(mount, between(*l.T_odom_base, *l.T_odom_laser));
      dx = std::max(dx, std::hypot(e.x, e.y));
      dyaw = std::max(dyaw, std::abs(e.yaw));
    }
  return {dx, dyaw};
}

/// Poses this close on every line are one offset, not two estimates.
constexpr double kSameMountM = 1e-3, kSameMountRad = 1e-3;

/// The mount: --lidar-mount, else PARAM lines, else the laser lines' poses where every line
/// has the same robot_pose^-1 laser_pose (the offset the logger was configured with: CARMEN
/// writes laser_pose as robot_pose * its front laser offset) or where asked, else identity.
/// Notes when the lines' robot_pose^-1 laser_pose disagrees with it.
SE2 lidarMount(const CarmenLog& log, const std::vector<CarmenLaser>& lasers, const ImportParams& p,
               const std::string& file, ImportResult& r) {
  const std::string name(carmenMessageName(lasers.front().type));
  std::optional<SE2> from_poses;
  for (const auto& l : lasers)
    if (l.T_odom_base && l.T_odom_laser) {
      from_poses = between(*l.T_odom_base, *l.T_odom_laser);
      break;
    }
  const bool one_offset = from_poses && [&] {
    const auto [dx, dyaw] = mountDeparture(lasers, *from_poses);
    return dx <= kSameMountM && dyaw <= kSameMountRad;
  }();
  std::string source;
  SE2 mount;
  if (p.T_base_lidar) {
    mount = *p.T_base_lidar;
    source = "--lidar-mount";
  } else if (const auto m = paramMount(log, lasers.front().type, file, source)) {
    mount = *m;
  } else if (p.lidar_mount_from_poses) {
    if (!from_poses)
      throw InputError(file, "--lidar-mount-from-poses: " + name + " lines carry no poses");
    mount = *from_poses;
    source = "robot_pose^-1 laser_pose of the first " + name + " line (--lidar-mount-from-poses)";
  } else if (one_offset) {
    mount = *from_poses;
    source = "robot_pose^-1 laser_pose, the same on every " + name +
             " line (the offset the logger was configured with; the log has no mount PARAM)";
  } else {
    source = "nothing: the log has no mount PARAM, identity used (give --lidar-mount x,y,yaw_deg)";
  }
  r.summary.lidar_mount = poseText(mount) + " from " + source;
  const auto [dx, dyaw] = mountDeparture(lasers, mount);
  if (dx > kSameMountM || dyaw > kSameMountRad)
    r.notes.push_back("the " + name +
                      " lines' laser_pose differs from robot_pose * mount by up to " + number(dx) +
                      " m, " + number(dyaw / kDegree) +
                      " deg (first line: robot_pose^-1 laser_pose = " + poseText(*from_poses) +
                      "); the mount was not taken from the poses (--lidar-mount-from-poses does)");
  return mount;
}

std::string scansText(const std::vector<CarmenLaser>& lasers) {
  const CarmenLaserType type = lasers.front().type;
  std::size_t lo = lasers.front().scan.size(), hi = lo;
  for (const auto& l : lasers) {
    lo = std::min(lo, l.scan.size());
    hi = std::max(hi, l.scan.size());
  }
  std::string s = std::to_string(lasers.size()) + " " + std::string(carmenMessageName(type)) +
                  " lines, " + std::to_string(lo) + (hi > lo ? ".." + std::to_string(hi) : "") +
                  " beams";
  if (type == CarmenLaserType::kFlaser || type == CarmenLaserType::kRlaser)
    return s + "; the lines carry no angles: from -90 deg every " +
           number(lasers.front().scan.angle_increment_rad / kDegree) +
           " deg and 80 m max range assumed (CARMEN's convention)";
  return s + "; angles and max range from each line";
}

std::string timeIncrement(const CarmenLog& log, const ImportParams& p, const std::string& file,
                          double& value) {
  if (p.time_increment_s) {
    value = *p.time_increment_s;
    return number(value) + " s (--time-increment)";
  }
  if (const auto v = carmenParam(log, "slamprep_time_increment", file)) {
    if (!(*v >= 0)) throw InputError(file, "PARAM slamprep_time_increment: must be >= 0");
    value = *v;
    return number(value) + " s (PARAM slamprep_time_increment)";
  }
  value = 0.0;
  return "0: CARMEN logs have no per-beam timing, scans are taken as instantaneous (give the "
         "sensor's with --time-increment SECONDS; de-skew refuses time_increment 0)";
}

/// The odometry's stale-run report, named after the odometry it checks (s.odometry).
StaleReport& staleReport(ImportSummary& s) {
  s.stale.emplace_back();
  s.stale.back().stream = s.odometry;
  return s.stale.back();
}

/// --max-range and the no-return value, recorded. No note on a range_max far beyond the readings:
/// FLASER's 80 m is CARMEN's convention, not a claim of the log (the summary still gives the
/// percentile).
void noteRange(RangeReport range, ImportResult& r) {
  range.suspect = false;
  r.summary.range = range;
  if (range.max_range_m) r.dataset.info.config["max_range_m"] = *range.max_range_m;
  if (range.no_return_applied) {
    r.dataset.info.config["no_return_value_m"] = range.no_return->value_m;
    r.notes.push_back(range.noReturnText());
  }
}

/// What the import did not take from the log as written: reordered or dropped late stamps, the
/// other lasers, messages not read, repeated lines.
void countLeftOut(const CarmenLog& log, CarmenLaserType type, const ImportParams& p,
                  ImportSummary& s) {
  for (const auto& [stream, lines] : log.out_of_order)
    if (p.drop_late_stamps)
      s.dropped[stream + ": stamped at or after a later " + stream +
                " line (--out-of-order drop)"] = lines;
    else
      s.reordered[stream] = lines;
  for (const auto& [other, lines] : log.lasers)
    if (other != type)
      s.dropped[std::string(carmenMessageName(other)) + ": another laser (--laser " +
                std::string(carmenMessageName(other)) + " imports it)"] = lines.size();
  for (const auto& [message, lines] : log.skipped) s.dropped[message + ": not read"] = lines;
  for (const auto& [stream, lines] : log.repeated)
    s.dropped[stream + ": identical to the previous " + stream + " line"] = lines;
}

/// The laser's scans with the log's beam timing and the --max-range rule; `where` names each
/// scan's line. CARMEN has no scan_time: the scans' median spacing.
void addScans(const std::vector<CarmenLaser>& lasers, double time_increment,
              const std::string& file, const ImportParams& p, ImportResult& result,
              std::vector<std::string>& where) {
  Dataset& d = result.dataset;
  RangeHistogram ranges;
  std::size_t cut = 0;
  std::vector<double> stamps;
  for (const auto& l : lasers) {
    ScanRecord r;
    r.scan = l.scan;
    r.scan.time_increment_s = time_increment;
    ranges.add(r.scan);
    if (p.max_range_m) cut += applyMaxRange(r.scan, *p.max_range_m);
    stamps.push_back(r.scan.stamp_s);
    d.scans.push_back(std::move(r));
    where.push_back(file + ":" + std::to_string(l.line));
  }
  RangeReport range = rangeReport(ranges, p.max_range_m, cut);
  if (range.no_return) {
    for (auto& r : d.scans) applyNoReturnValue(r.scan, range.no_return->value_m);
    range.no_return_applied = true;
  }
  noteRange(range, result);
  const double scan_time = medianSpacing(stamps);
  for (auto& r : d.scans) r.scan.scan_time_s = scan_time;
}

}  // namespace

ImportResult importCarmen(std::string_view text, const std::string& file, const ImportParams& p) {
  checkParams(p);
  const CarmenLog log = parseCarmen(text, file, {p.reorder_tolerance_s, p.drop_late_stamps});
  const CarmenLaserType type = chooseLaser(log, p.laser, file);
  const std::vector<CarmenLaser>& lasers = log.lasers.at(type);
  ImportResult result;
  ImportSummary& s = result.summary;
  Dataset& d = result.dataset;
  countLeftOut(log, type, p, s);
  const PoseSeries odometry = odometryOf(log, lasers, p, file, s);
  d.odom_nominal = dropStaleOdometry(odometry, staleReport(s));
  const std::optional<DiffDriveParams> nominal = nominalGeometry(log, p, file, s);
  double lateral = 0.0;
  if (nominal)
    d.encoders = encodersFromPoses(d.odom_nominal, *nominal, p.ticks_per_revolution, &lateral);
  d.info = importedInfo(p, nominal.value_or(DiffDriveParams{}), file, "carmen",
                        nominal ? "derived from the odometry poses with the nominal geometry"
                                : "none: no nominal geometry",
                        nominal ? "odometry_poses" : "");
  d.info.config["odometry_from"] = s.odometry;
  d.info.config["nominal_geometry_from"] = nominal ? s.nominal_geometry : "absent";
  d.info.T_base_lidar = lidarMount(log, lasers, p, file, result);
  d.info.config["lidar_mount_from"] = s.lidar_mount;
  double time_increment = 0.0;
  s.time_increment = timeIncrement(log, p, file, time_increment);
  s.scans = scansText(lasers);
  std::vector<std::string> where;
  addScans(lasers, time_increment, file, p, result, where);
  attachOdometry(d, p.trim, where, result.notes);
  if (d.scans.size() < lasers.size())
    s.dropped["scans outside the odometry (--trim)"] = lasers.size() - d.scans.size();
  if (lateral > 1e-6)
    result.notes.push_back("odometry has sideways steps up to " + number(lateral) +
                           " m that no wheel motion explains (dropped from the encoders)");
  return result;
}

}  // namespace slamprep::eval
