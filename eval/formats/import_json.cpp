#include "slamprep/eval/formats/import_json.hpp"

#include <cmath>
#include <numbers>

namespace slamprep::eval {
namespace {

using nlohmann::ordered_json;

ordered_json orNull(const std::string& s) {
  return s.empty() ? ordered_json() : ordered_json(s);
}

ordered_json rangeJson(const std::optional<RangeReport>& r) {
  if (!r) return nullptr;
  return {
      {"max_range_m", r->max_range_m ? ordered_json(*r->max_range_m) : ordered_json()},
      {"range_max_m", r->range_max_m},
      {"readings", r->readings},
      {"readings_p999_m", r->p999_m},
      {"largest_reading_m", r->largest_m},
      {"cut_readings", r->cut},
      {"range_max_suspect", r->suspect},
      {"no_return_value_m", r->no_return ? ordered_json(r->no_return->value_m) : ordered_json()},
      {"no_return_readings", r->no_return ? r->no_return->readings : 0},
      {"no_return_applied", r->no_return_applied},
      {"rule", "suspect when range_max > 2 x the 99.9th percentile of the finite readings"},
      {"text", r->text()}};
}

ordered_json staleJson(const StaleReport& s) {
  ordered_json runs = ordered_json::array();
  for (const StaleRun& r : s.runs)
    runs.push_back({{"start_s", r.start_s},
                    {"span_s", r.span_s},
                    {"samples", r.repeats + 1},
                    {"jump", {r.jump[0], r.jump[1]}}});
  const StaleRun* l = s.longest();
  return {{"stream", s.stream},
          {"samples", s.samples},
          {"repeated_runs", s.repeated_runs},
          {"stale_runs", s.runs.size()},
          {"dropped_samples", s.dropped()},
          {"units", {s.units[0], s.units[1]}},
          {"threshold", {s.threshold[0], s.threshold[1]}},
          {"longest_span_s", l ? ordered_json(l->span_s) : ordered_json()},
          {"runs", runs}};
}

ordered_json spikesJson(const TwistSpikes& s) {
  return {{"count", s.count},
          {"threshold", s.threshold},
          {"largest", s.count ? ordered_json(s.largest) : ordered_json()},
          {"largest_at_s", s.count ? ordered_json(s.largest_at_s) : ordered_json()},
          {"derived_there", s.count ? ordered_json(s.derived_there) : ordered_json()}};
}

ordered_json twistJson(const std::optional<TwistSpikeReport>& t) {
  if (!t) return nullptr;
  return {{"stream", t->stream},
          {"angular_z_rad_s", spikesJson(t->angular)},
          {"linear_x_m_s", spikesJson(t->linear)},
          {"rule", "|residual - median| > 10 x 1.4826 MAD and |twist| > 10 rad/s or 5 m/s"}};
}

std::string configText(const Dataset& d, const char* key) {
  const auto it = d.info.config.find(key);
  return it != d.info.config.end() && it->is_string() ? it->get<std::string>() : "";
}

}  // namespace

ordered_json importSummaryJson(const std::string& input, const std::string& format,
                               const std::string& out, const ImportSummary& s, const Dataset& d,
                               const ImportCounts& counts, const std::vector<std::string>& notes) {
  const SE2& m = d.info.T_base_lidar;
  const DiffDriveParams& g = d.info.nominal_geometry;
  ordered_json stale = ordered_json::array();
  for (const StaleReport& r : s.stale) stale.push_back(staleJson(r));
  return {{"input", input},
          {"format", format},
          {"out", out},
          {"storage", orNull(s.storage)},
          {"topics", s.topics},
          {"counts",
           {{"scans", counts.scans},
            {"encoder_samples", d.encoders.size()},
            {"odometry_poses", d.odom_nominal.size()},
            {"odometry_logged_poses", d.odometry_logged.size()},
            {"imu_samples", d.imu.size()}}},
          {"scans", orNull(s.scans)},
          {"odometry", orNull(s.odometry)},
          {"encoders_from", orNull(configText(d, "encoders_from"))},
          {"lidar_mount",
           {{"x_m", m.x},
            {"y_m", m.y},
            {"yaw_deg", m.yaw * 180 / std::numbers::pi},
            {"from",
             orNull(s.lidar_mount.empty() ? configText(d, "lidar_mount_from") : s.lidar_mount)}}},
          {"nominal_geometry",
           {{"radius_left_m", g.radius_left_m},
            {"radius_right_m", g.radius_right_m},
            {"wheel_base_m", g.wheel_base_m},
            {"from", orNull(s.nominal_geometry)}}},
          {"time_increment", orNull(s.time_increment)},
          {"max_range", rangeJson(s.range)},
          {"stale_odometry", stale},
          {"twist_spikes", twistJson(s.twist_spikes)},
          {"reordered", s.reordered},
          {"dropped", s.dropped},
          {"notes", notes},
          {"sensor_agreement", nullptr}};
}

}  // namespace slamprep::eval
