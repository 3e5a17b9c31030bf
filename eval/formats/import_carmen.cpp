#include <algorithm>
#include <cmath>

#include "core/error.hpp"
#include "eval/formats/carmen.hpp"
#include "eval/formats/import.hpp"
#include "eval/formats/import_common.hpp"
#include "eval/formats/text_io.hpp"

namespace slamprep::eval {
namespace {

/// The median spacing of the scan stamps: CARMEN has no scan_time.
double medianSpacing(const std::vector<ScanRecord>& scans) {
  std::vector<double> dt;
  for (std::size_t i = 1; i < scans.size(); ++i)
    dt.push_back(scans[i].scan.stamp_s - scans[i - 1].scan.stamp_s);
  if (dt.empty()) return 0.0;
  std::nth_element(dt.begin(), dt.begin() + dt.size() / 2, dt.end());
  return dt[dt.size() / 2];
}

/// A PARAM value of a CARMEN log as a finite number; nullopt when the log has no such PARAM.
std::optional<double> carmenParam(const CarmenLog& log, const std::string& name,
                                  const std::string& file) {
  const auto it = log.params.find(name);
  if (it == log.params.end()) return std::nullopt;
  return slamprep::eval::parseFiniteDouble(it->second.value, {file, it->second.line}, name);
}

/// The nominal geometry: the given one, else the log's PARAM slamprep_nominal_* lines, else
/// DiffDriveParams{} (with a note saying so).
DiffDriveParams nominalGeometry(const CarmenLog& log, const ImportParams& p,
                                const std::string& file, std::vector<std::string>& notes) {
  DiffDriveParams nominal;
  if (p.nominal_geometry) {
    nominal = *p.nominal_geometry;
  } else {
    const auto r_L = carmenParam(log, "slamprep_nominal_r_L", file);
    const auto r_R = carmenParam(log, "slamprep_nominal_r_R", file);
    const auto b = carmenParam(log, "slamprep_nominal_b", file);
    if (r_L && r_R && b) {
      nominal = {*r_L, *r_R, *b};
      checkGeometry(nominal, file + ": PARAM slamprep_nominal_*");
    } else {
      notes.push_back("no nominal geometry given or in the log: r_L = r_R = " +
                      std::to_string(nominal.radius_left_m) +
                      " m, b = " + std::to_string(nominal.wheel_base_m) +
                      " m assumed (calibration results are relative to it)");
    }
  }
  return nominal;
}

}  // namespace

ImportResult importCarmen(std::string_view text, const std::string& file, const ImportParams& p) {
  checkParams(p);
  const CarmenLog log = parseCarmen(text, file);
  if (log.lasers.empty()) throw InputError(file, "no ROBOTLASER1 or FLASER lines");
  if (log.odometry.size() < 2) throw InputError(file, "fewer than 2 ODOM lines");
  ImportResult result;
  Dataset& d = result.dataset;
  const DiffDriveParams nominal = nominalGeometry(log, p, file, result.notes);
  double time_increment =
      p.time_increment_s.value_or(carmenParam(log, "slamprep_time_increment", file).value_or(0.0));
  if (!(time_increment >= 0)) throw InputError(file, "PARAM slamprep_time_increment: must be >= 0");
  for (const auto& o : log.odometry) d.odom_nominal.push_back(o.stamp_s, o.T_odom_base);
  double lateral = 0.0;
  d.encoders = encodersFromPoses(d.odom_nominal, nominal, p.ticks_per_revolution, &lateral);
  d.info = importedInfo(p, nominal, file, "carmen",
                        "derived from the ODOM poses with the nominal geometry");
  // The mount: laser_pose = robot_pose * T_base_lidar on every line.
  const SE2 mount = between(log.lasers[0].T_odom_base, log.lasers[0].T_odom_laser);
  double spread = 0.0;
  for (const auto& l : log.lasers) {
    const SE2 m = between(l.T_odom_base, l.T_odom_laser);
    spread = std::max({spread, std::hypot(m.x - mount.x, m.y - mount.y),
                       std::abs(normalizeAngle(m.yaw - mount.yaw))});
  }
  d.info.T_base_lidar = p.T_base_lidar.value_or(mount);
  if (!p.T_base_lidar && spread > 1e-3)
    result.notes.push_back("laser_pose vs robot_pose varies by up to " + std::to_string(spread) +
                           " (m or rad) across the log: the first line's mount was taken");
  std::vector<std::string> where;
  for (const auto& l : log.lasers) {
    ScanRecord r;
    r.scan = l.scan;
    r.scan.time_increment_s = time_increment;
    d.scans.push_back(std::move(r));
    where.push_back(file + ":" + std::to_string(l.line));
  }
  const double scan_time = medianSpacing(d.scans);
  for (auto& r : d.scans) r.scan.scan_time_s = scan_time;
  attachOdometry(d, p.trim, where, result.notes);
  if (lateral > 1e-6)
    result.notes.push_back("odometry has sideways steps up to " + std::to_string(lateral) +
                           " m that no wheel motion explains (dropped from the encoders)");
  if (time_increment == 0)
    result.notes.push_back(
        "CARMEN has no time between beams: time_increment = 0, de-skew will "
        "refuse these scans (give --time-increment)");
  if (log.skipped_lines)
    result.notes.push_back(std::to_string(log.skipped_lines) + " lines of other messages skipped");
  return result;
}

}  // namespace slamprep::eval
