#include "slamprep/eval/formats/import_common.hpp"

#include <algorithm>
#include <cmath>

#include "slamprep/core/error.hpp"
#include "slamprep/core/odometry.hpp"

namespace slamprep::eval {

void checkGeometry(const DiffDriveParams& g, const std::string& where) {
  for (double v : {g.radius_left_m, g.radius_right_m, g.wheel_base_m})
    if (!std::isfinite(v) || v <= 0) throw InputError(where, "wheel radii and base must be > 0");
}

void checkParams(const ImportParams& p) {
  if (p.nominal_geometry) checkGeometry(*p.nominal_geometry, "--wheel-radius/--wheel-base");
  if (p.ticks_per_revolution <= 0) throw InputError("--ticks-per-revolution", "must be > 0");
  if (p.max_range_m && (!std::isfinite(*p.max_range_m) || *p.max_range_m <= 0))
    throw InputError("--max-range", "must be finite and > 0");
  if (p.time_increment_s && (!std::isfinite(*p.time_increment_s) || *p.time_increment_s < 0))
    throw InputError("--time-increment", "must be finite and >= 0");
  if (!std::isfinite(p.reorder_tolerance_s) || p.reorder_tolerance_s < 0)
    throw InputError("--reorder-tolerance", "must be finite and >= 0");
}

/// Attaches the odometry to the scans; refuses (or with trim drops) scans it does not cover.
bool attachOdometryTo(ScanRecord& r, const PoseSeries& odometry, bool trim,
                      const std::string& where) {
  if (!odometry.covers(r.scan.stamp_s) || !odometry.covers(r.scan.endTime())) {
    if (trim) return false;
    throw InputError(where,
                     "scan at " + std::to_string(r.scan.stamp_s) + ".." +
                         std::to_string(r.scan.endTime()) + " s is not covered by the odometry (" +
                         (odometry.empty() ? std::string("none")
                                           : std::to_string(odometry.frontStamp()) + ".." +
                                                 std::to_string(odometry.backStamp()) + " s") +
                         "); without --no-trim such scans are dropped");
  }
  r.T_odom_base_nominal = odometry.at(r.scan.stamp_s);
  return true;
}

std::string trimmedNote(std::size_t dropped) {
  return dropped == 0
             ? ""
             : std::to_string(dropped) +
                   " scans outside the odometry (before its first sample or after its last) "
                   "were dropped (--trim, the default; --no-trim refuses them)";
}

void attachOdometry(Dataset& d, bool trim, const std::vector<std::string>& scan_where,
                    std::vector<std::string>& notes) {
  std::vector<ScanRecord> kept;
  for (std::size_t i = 0; i < d.scans.size(); ++i)
    if (attachOdometryTo(d.scans[i], d.odom_nominal, trim, scan_where[i]))
      kept.push_back(std::move(d.scans[i]));
  if (kept.size() < d.scans.size()) notes.push_back(trimmedNote(d.scans.size() - kept.size()));
  if (kept.empty()) throw InputError(scan_where.empty() ? "" : scan_where[0], "no scan left");
  d.scans = std::move(kept);
}

DatasetInfo importedInfo(const ImportParams& p, const DiffDriveParams& nominal,
                         const std::string& file, const char* format, const std::string& encoders,
                         const std::string& encoders_from) {
  DatasetInfo info;
  info.nominal_geometry = nominal;
  info.ticks_per_revolution = p.ticks_per_revolution;
  info.config = {{"imported_from", file}, {"format", format}, {"encoders", encoders}};
  if (!encoders_from.empty()) info.config["encoders_from"] = encoders_from;
  return info;
}

std::int64_t ticksOf(double angle_rad, double rad_per_tick, const std::string& where) {
  const double t = std::round(angle_rad / rad_per_tick);
  if (!std::isfinite(t) || std::abs(t) > 9e18)
    throw InputError(where, "wheel angle " + std::to_string(angle_rad) + " rad out of range");
  return static_cast<std::int64_t>(t);
}

EncoderLog encodersFromPoses(const PoseSeries& poses, const DiffDriveParams& g,
                             int ticks_per_revolution, double* max_lateral_m) {
  EncoderLog out;
  const double rad_per_tick = radiansPerTick(ticks_per_revolution);
  double phi_l = 0.0, phi_r = 0.0, lateral = 0.0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    if (k > 0) {
      const Eigen::Vector3d xi = between(poses[k - 1].value, poses[k].value).log();
      phi_l += (xi.x() - xi.z() * g.wheel_base_m / 2) / g.radius_left_m;
      phi_r += (xi.x() + xi.z() * g.wheel_base_m / 2) / g.radius_right_m;
      lateral = std::max(lateral, std::abs(xi.y()));
    }
    const std::string where = "odometry sample " + std::to_string(k);
    out.push_back({poses[k].stamp_s, ticksOf(phi_l, rad_per_tick, where),
                   ticksOf(phi_r, rad_per_tick, where)});
  }
  if (max_lateral_m) *max_lateral_m = lateral;
  return out;
}

}  // namespace slamprep::eval
