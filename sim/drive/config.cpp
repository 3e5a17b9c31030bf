#include "slamprep/sim/drive/config.hpp"

#include <charconv>
#include <cmath>
#include <numbers>
#include <sstream>

#include "slamprep/core/error.hpp"
#include "slamprep/sim/drive/rng.hpp"

namespace slamprep::sim {
namespace {

template <typename Config, typename Visitor>
void visitRobotFields(Config& c, Visitor&& v) {
  auto& r = c.robot;
  v("robot.radius_left_m", r.geometry.radius_left_m);
  v("robot.radius_right_m", r.geometry.radius_right_m);
  v("robot.wheel_base_m", r.geometry.wheel_base_m);
  v("robot.wheel_width_m", r.wheel_width_m);
  v("robot.wheel_mass_kg", r.wheel_mass_kg);
  v("robot.chassis_mass_kg", r.chassis_mass_kg);
  v("robot.max_wheel_torque_nm", r.max_wheel_torque_nm);
  v("robot.wheel_friction", r.wheel_friction);
  v("robot.caster_radius_m", r.caster_radius_m);
  v("robot.caster_friction", r.caster_friction);
  v("robot.chassis_length_m", r.chassis_length_m);
  v("robot.chassis_width_m", r.chassis_width_m);
  v("robot.chassis_height_m", r.chassis_height_m);
  v("robot.chassis_clearance_m", r.chassis_clearance_m);
  v("robot.caster_offset_m", r.caster_offset_m);
  v("nominal.radius_left_error", c.nominal.radius_left_error);
  v("nominal.radius_right_error", c.nominal.radius_right_error);
  v("nominal.wheel_base_error", c.nominal.wheel_base_error);
  v("nominal.lidar_mount_error.x_m", c.nominal.lidar_mount_x_error_m);
  v("nominal.lidar_mount_error.y_m", c.nominal.lidar_mount_y_error_m);
  v("nominal.lidar_mount_error.yaw_rad", c.nominal.lidar_mount_yaw_error_rad);
}

template <typename Config, typename Visitor>
void visitSensorFields(Config& c, Visitor&& v) {
  auto& l = c.lidar;
  v("lidar.rate_hz", l.rate_hz);
  v("lidar.sweep_s", l.sweep_s);
  v("lidar.free_running", l.free_running);
  v("lidar.beams_per_revolution", l.beams_per_revolution);
  v("lidar.fov_rad", l.fov_rad);
  v("lidar.range_min_m", l.range_min_m);
  v("lidar.range_max_m", l.range_max_m);
  v("lidar.range_noise_m", l.range_noise_m);
  v("lidar.range_noise_correlation", l.range_noise_correlation);
  v("lidar.range_noise_fixed_m", l.range_noise_fixed_m);
  v("lidar.range_noise_fixed_length_m", l.range_noise_fixed_length_m);
  v("lidar.range_bias_by_beam_m", l.range_bias_by_beam_m);
  v("lidar.range_bias_by_range_m", l.range_bias_by_range_m);
  v("lidar.clockwise", l.clockwise);
  v("lidar.mount.x_m", l.T_base_lidar.x);
  v("lidar.mount.y_m", l.T_base_lidar.y);
  v("lidar.mount.yaw_rad", l.T_base_lidar.yaw);
  v("lidar.height_m", l.height_m);
  v("encoders.ticks_per_revolution", c.encoders.ticks_per_revolution);
  v("encoders.rate_hz", c.encoders.rate_hz);
  v("encoders.slip_sigma", c.encoders.slip_sigma);
  v("encoders.slip_tau_s", c.encoders.slip_tau_s);
  v("encoders.turn_slip_sigma", c.encoders.turn_slip_sigma);
  v("encoders.common_slip_sigma", c.encoders.common_slip_sigma);
  v("imu.rate_hz", c.imu.rate_hz);
  v("imu.gyro_noise_radps", c.imu.gyro_noise_radps);
  v("imu.gyro_bias_radps", c.imu.gyro_bias_radps);
  v("imu.accel_noise_mps2", c.imu.accel_noise_mps2);
  v("imu.accel_bias_x_mps2", c.imu.accel_bias_x_mps2);
  v("imu.accel_bias_y_mps2", c.imu.accel_bias_y_mps2);
  v("odometry.heading_from", c.odometry.heading_from);
}

template <typename Config, typename Visitor>
void visitFaultFields(Config& c, Visitor&& v) {
  auto& f = c.faults;
  v("faults.enable", f.enable);
  v("faults.encoder_spikes.rate_hz", f.encoder_spike_rate_hz);
  v("faults.encoder_spikes.ticks", f.encoder_spike_ticks);
  v("faults.encoder_dropouts.rate_hz", f.encoder_dropout_rate_hz);
  v("faults.encoder_dropouts.duration_s", f.encoder_dropout_duration_s);
  v("faults.stamp_jitter.sigma_s", f.stamp_jitter_sigma_s);
  v("faults.stamp_jitter.encoders_sigma_s", f.stamp_jitter_encoders_sigma_s);
  v("faults.stamp_jitter.imu_sigma_s", f.stamp_jitter_imu_sigma_s);
  v("faults.stamp_jitter.scans_sigma_s", f.stamp_jitter_scans_sigma_s);
  v("faults.stamp_jitter.encoders_sampling_sigma_s", f.stamp_jitter_encoders_sampling_sigma_s);
  v("faults.read_jitter.encoders_sigma_s", f.read_jitter_encoders_sigma_s);
  v("faults.read_jitter.encoders_correlation_s", f.read_jitter_encoders_correlation_s);
  v("faults.read_jitter.scans_sigma_s", f.read_jitter_scans_sigma_s);
  v("faults.clock_offset.offset_s", f.clock_offset_s);
  v("faults.dropped_scans.probability", f.dropped_scan_probability);
  v("faults.dropped_beams.probability", f.dropped_beam_probability);
  v("faults.dropped_beams.by_angle", f.dropped_beam_by_angle);
  v("faults.dropped_beams.by_range", f.dropped_beam_by_range);
  v("faults.dropped_beams.range_bin_m", f.dropped_beam_range_bin_m);
  v("faults.imu_bias_drift.gyro_walk_radps_per_sqrt_s", f.imu_gyro_bias_walk_radps);
  v("faults.stale_odometry.rate_hz", f.stale_odometry_rate_hz);
  v("faults.stale_odometry.min_hold_s", f.stale_odometry_min_hold_s);
  v("faults.stale_odometry.max_hold_s", f.stale_odometry_max_hold_s);
  v("faults.held_robot.rate_hz", f.held_robot_rate_hz);
  v("faults.held_robot.min_duration_s", f.held_robot_min_duration_s);
  v("faults.held_robot.max_duration_s", f.held_robot_max_duration_s);
}

// One list of (key, field) pairs drives JSON output, JSON input and overrides alike.
template <typename Config, typename Visitor>
void visitFields(Config& c, Visitor&& v) {
  v("world", c.world);
  v("scenario", c.scenario);
  v("duration_s", c.duration_s);
  v("seed", c.seed);
  v("mode", c.mode);
  v("physics_rate_hz", c.physics_rate_hz);
  v("solver_iterations", c.solver_iterations);
  v("path_margin_m", c.path_margin_m);
  v("start_jitter.position_m", c.start_jitter.position_m);
  v("start_jitter.yaw_deg", c.start_jitter.yaw_deg);
  visitRobotFields(c, v);
  visitSensorFields(c, v);
  visitFaultFields(c, v);
  v("people.count", c.people.count);
  v("people.distance_m", c.people.distance_m);
  v("people.correlation_s", c.people.correlation_s);
  v("people.radius_m", c.people.radius_m);
}

nlohmann::json::json_pointer pointer(const std::string& dotted) {
  std::string p = "/" + dotted;
  for (char& ch : p) {
    if (ch == '.') ch = '/';
  }
  return nlohmann::json::json_pointer(p);
}

// ---- Values from JSON --------------------------------------------------------------------------

void fromJsonValue(const nlohmann::json& j, double& out, const std::string& at) {
  if (!j.is_number()) throw InputError(at, "expected a number");
  out = j.get<double>();
}
void fromJsonValue(const nlohmann::json& j, int& out, const std::string& at) {
  if (!j.is_number_integer()) throw InputError(at, "expected a whole number");
  const auto v = j.get<std::int64_t>();
  if (v < -1000000000 || v > 1000000000) throw InputError(at, "out of range");
  out = static_cast<int>(v);
}
void fromJsonValue(const nlohmann::json& j, std::uint64_t& out, const std::string& at) {
  if (!j.is_number_unsigned()) throw InputError(at, "expected a whole number >= 0");
  out = j.get<std::uint64_t>();
}
void fromJsonValue(const nlohmann::json& j, bool& out, const std::string& at) {
  if (!j.is_boolean()) throw InputError(at, "expected true or false");
  out = j.get<bool>();
}
void fromJsonValue(const nlohmann::json& j, std::string& out, const std::string& at) {
  if (!j.is_string()) throw InputError(at, "expected a string");
  out = j.get<std::string>();
}
// A name of `table`; a value that is not a string is shown as JSON ("unknown mode '3'").
template <typename E, std::size_t N>
E enumFromJson(const nlohmann::json& j, const EnumNames<E, N>& table, std::string_view what,
               const std::string& at) {
  return parseName(table, j.is_string() ? j.get<std::string>() : j.dump(), what, at);
}
void fromJsonValue(const nlohmann::json& j, SimMode& out, const std::string& at) {
  out = enumFromJson(j, kSimModeNames, "mode", at);
}
void fromJsonValue(const nlohmann::json& j, OdometryHeading& out, const std::string& at) {
  out = enumFromJson(j, kOdometryHeadingNames, "heading", at);
}
nlohmann::json toJsonValue(SimMode mode) {
  return std::string(nameOf(kSimModeNames, mode));
}
nlohmann::json toJsonValue(OdometryHeading heading) {
  return std::string(nameOf(kOdometryHeadingNames, heading));
}
nlohmann::json toJsonValue(const FaultSet& faults) {
  return toString(faults);
}
void fromJsonValue(const nlohmann::json& j, FaultSet& out, const std::string& at) {
  if (!j.is_string()) throw InputError(at, "expected a string of fault names");
  std::string error;
  const auto set = parseFaultSet(j.get<std::string>(), &error);
  if (!set) throw InputError(at, error);
  out = *set;
}
template <typename T>
nlohmann::json toJsonValue(const T& value) {
  return value;
}

// ---- Values from command-line text -------------------------------------------------------------

template <typename T>
bool parseNumber(const std::string& text, T& out) {
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, out);
  return ec == std::errc() && ptr == end;
}

void fromText(const std::string& text, double& out, const std::string& at) {
  if (!parseNumber(text, out) || !std::isfinite(out)) {
    throw InputError(at, "expected a finite number, got '" + text + "'");
  }
}
void fromText(const std::string& text, int& out, const std::string& at) {
  if (!parseNumber(text, out)) throw InputError(at, "expected a whole number, got '" + text + "'");
}
void fromText(const std::string& text, std::uint64_t& out, const std::string& at) {
  if (!parseNumber(text, out)) {
    throw InputError(at, "expected a whole number >= 0, got '" + text + "'");
  }
}
void fromText(const std::string& text, bool& out, const std::string& at) {
  if (text == "true" || text == "1") {
    out = true;
  } else if (text == "false" || text == "0") {
    out = false;
  } else {
    throw InputError(at, "expected true or false, got '" + text + "'");
  }
}
void fromText(const std::string& text, std::string& out, const std::string&) {
  out = text;
}
void fromText(const std::string& text, SimMode& out, const std::string& at) {
  fromJsonValue(nlohmann::json(text), out, at);
}
void fromText(const std::string& text, FaultSet& out, const std::string& at) {
  fromJsonValue(nlohmann::json(text), out, at);
}
void fromText(const std::string& text, OdometryHeading& out, const std::string& at) {
  fromJsonValue(nlohmann::json(text), out, at);
}

// ---- Validation ----------------------------------------------------------------------------

struct Checker {
  const std::string& where;

  template <typename T>
  void fail(const std::string& key, const std::string& what, T value) const {
    std::ostringstream msg;
    msg << what << " (got " << value << ")";
    throw InputError(where.empty() ? key : where + ": " + key, msg.str());
  }
  void positive(const std::string& key, double value) const {
    if (!(value > 0.0)) fail(key, "must be positive", value);
  }
  void nonNegative(const std::string& key, double value) const {
    if (!(value >= 0.0)) fail(key, "must not be negative", value);
  }
  /// A fault's events per second: every event is drawn up front, so 1e9 Hz would never end.
  void faultRate(const std::string& key, double value) const {
    nonNegative(key, value);
    if (value > kMaxFaultRate_hz) fail(key, "must be at most 100 (events per second)", value);
  }
};

void validateFaults(const Checker& check, const FaultsConfig& f) {
  check.faultRate("faults.encoder_spikes.rate_hz", f.encoder_spike_rate_hz);
  if (f.encoder_spike_ticks < 1)
    check.fail("faults.encoder_spikes.ticks", "must be at least 1", f.encoder_spike_ticks);
  check.faultRate("faults.encoder_dropouts.rate_hz", f.encoder_dropout_rate_hz);
  check.positive("faults.encoder_dropouts.duration_s", f.encoder_dropout_duration_s);
  check.nonNegative("faults.stamp_jitter.sigma_s", f.stamp_jitter_sigma_s);
  check.nonNegative("faults.stamp_jitter.encoders_sampling_sigma_s",
                    f.stamp_jitter_encoders_sampling_sigma_s);
  for (const auto& [key, sigma] :
       {std::pair{"faults.stamp_jitter.encoders_sigma_s", f.stamp_jitter_encoders_sigma_s},
        std::pair{"faults.stamp_jitter.imu_sigma_s", f.stamp_jitter_imu_sigma_s},
        std::pair{"faults.stamp_jitter.scans_sigma_s", f.stamp_jitter_scans_sigma_s}})
    if (!(sigma >= 0.0 || sigma == -1.0)) check.fail(key, "must be >= 0, or -1 for sigma_s", sigma);
  check.nonNegative("faults.read_jitter.encoders_sigma_s", f.read_jitter_encoders_sigma_s);
  check.nonNegative("faults.read_jitter.encoders_correlation_s",
                    f.read_jitter_encoders_correlation_s);
  check.nonNegative("faults.read_jitter.scans_sigma_s", f.read_jitter_scans_sigma_s);
  if (!(std::abs(f.clock_offset_s) <= 1.0))
    check.fail("faults.clock_offset.offset_s", "must be within [-1, 1] s", f.clock_offset_s);
  for (const auto& [key, p] :
       {std::pair{"faults.dropped_scans.probability", f.dropped_scan_probability},
        std::pair{"faults.dropped_beams.probability", f.dropped_beam_probability}})
    if (!(p >= 0.0 && p <= 1.0)) check.fail(key, "must be in [0, 1]", p);
  for (const auto& [key, text] :
       {std::pair{"faults.dropped_beams.by_angle", &f.dropped_beam_by_angle},
        std::pair{"faults.dropped_beams.by_range", &f.dropped_beam_by_range}}) {
    std::string error;
    if (!parseFactors(*text, &error))
      check.fail(key, "expected comma-separated factors: " + error, *text);
  }
  check.positive("faults.dropped_beams.range_bin_m", f.dropped_beam_range_bin_m);
  check.nonNegative("faults.imu_bias_drift.gyro_walk_radps_per_sqrt_s", f.imu_gyro_bias_walk_radps);
  // The lasting faults: a rate, and a length drawn from [min, max] with min > 0.
  const auto lasting = [&check](const std::string& prefix, double rate_hz, const char* length,
                                double min_s, double max_s) {
    check.faultRate(prefix + ".rate_hz", rate_hz);
    check.positive(prefix + ".min_" + length, min_s);
    if (!(max_s >= min_s))
      check.fail(prefix + ".max_" + length, "must not be below the minimum", max_s);
  };
  lasting("faults.stale_odometry", f.stale_odometry_rate_hz, "hold_s", f.stale_odometry_min_hold_s,
          f.stale_odometry_max_hold_s);
  lasting("faults.held_robot", f.held_robot_rate_hz, "duration_s", f.held_robot_min_duration_s,
          f.held_robot_max_duration_s);
}

}  // namespace

DiffDriveParams SimConfig::nominalGeometry() const {
  const DiffDriveParams& g = robot.geometry;
  return {g.radius_left_m * (1.0 + nominal.radius_left_error),
          g.radius_right_m * (1.0 + nominal.radius_right_error),
          g.wheel_base_m * (1.0 + nominal.wheel_base_error)};
}

SE2 SimConfig::nominalMount() const {
  const SE2& m = lidar.T_base_lidar;
  return {m.x + nominal.lidar_mount_x_error_m, m.y + nominal.lidar_mount_y_error_m,
          normalizeAngle(m.yaw + nominal.lidar_mount_yaw_error_rad)};
}

SE2 SimConfig::startPose(const SE2& T_world_start) const {
  if (!start_jitter.any()) return T_world_start;
  SplitMix64 rng(streamSeed(seed, RngStream::start_pose));
  const auto symmetric = [&rng](double half_width) {
    return half_width * (2.0 * rng.uniform() - 1.0);
  };
  const double dx = symmetric(start_jitter.position_m), dy = symmetric(start_jitter.position_m);
  const double dyaw = symmetric(start_jitter.yaw_deg * std::numbers::pi / 180.0);
  return SE2(T_world_start.x + dx, T_world_start.y + dy, normalizeAngle(T_world_start.yaw + dyaw));
}

std::vector<std::string> configKeys() {
  std::vector<std::string> keys;
  SimConfig config;
  visitFields(config, [&](const std::string& key, auto&) { keys.push_back(key); });
  return keys;
}

nlohmann::json toJson(const SimConfig& config, bool every_key) {
  nlohmann::json json = nlohmann::json::object();
  visitFields(config, [&](const std::string& key, const auto& value) {
    json[pointer(key)] = toJsonValue(value);
  });
  if (!every_key && !config.faults.enable.any()) json.erase("faults");
  if (!every_key && config.odometry.heading_from == OdometryHeading::wheels) json.erase("odometry");
  if (!every_key && !config.start_jitter.any()) json.erase("start_jitter");
  if (!every_key && config.people.count == 0) json.erase("people");
  return json;
}

SimConfig configFromJson(const nlohmann::json& json, const std::string& where) {
  if (!json.is_object()) throw InputError(where, "configuration must be a JSON object");
  const nlohmann::json flat = json.flatten();  // {"/lidar/rate_hz": 10, ...}
  SimConfig config;
  std::size_t used = 0;
  visitFields(config, [&](const std::string& key, auto& value) {
    const auto it = flat.find(pointer(key).to_string());
    if (it == flat.end()) return;
    fromJsonValue(*it, value, where + ": " + key);
    ++used;
  });
  if (used != flat.size()) {
    const std::vector<std::string> keys = configKeys();
    for (const auto& [path, value] : flat.items()) {
      // flatten() turns an empty object into a null leaf: nothing set there.
      if (value.is_null() && json.at(nlohmann::json::json_pointer(path)).is_object()) continue;
      std::string dotted = path.empty() ? path : path.substr(1);
      for (char& ch : dotted) {
        if (ch == '/') ch = '.';
      }
      if (std::find(keys.begin(), keys.end(), dotted) == keys.end()) {
        throw InputError(where + ": " + dotted, "unknown configuration key");
      }
    }
  }
  validate(config, where);
  return config;
}

void applyOverride(SimConfig& config, const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0) {
    throw InputError("--set " + assignment, "expected key=value (e.g. lidar.rate_hz=5)");
  }
  const std::string key = assignment.substr(0, eq);
  const std::string text = assignment.substr(eq + 1);
  const std::string at = "--set " + key;
  bool found = false;
  SimConfig updated = config;
  visitFields(updated, [&](const std::string& k, auto& value) {
    if (k != key) return;
    fromText(text, value, at);
    found = true;
  });
  if (!found) {
    throw InputError(at, "unknown configuration key (`slamprep simulate --help` lists them)");
  }
  validate(updated, "--set");
  config = updated;
}

namespace {

/// The run: its duration, physics rate and solver, path margin and start jitter.
void validateRun(const Checker& check, const SimConfig& c) {
  check.nonNegative("duration_s", c.duration_s);
  if (c.duration_s > 86400.0)
    check.fail("duration_s", "must be at most 86400 (one day)", c.duration_s);
  check.positive("physics_rate_hz", c.physics_rate_hz);
  if (c.physics_rate_hz > 1e6)
    check.fail("physics_rate_hz", "must be at most 1e6", c.physics_rate_hz);
  if (c.solver_iterations < 0 || c.solver_iterations > 1000) {
    check.fail("solver_iterations", "must be in [0, 1000] (0: the scene's default)",
               c.solver_iterations);
  }
  check.nonNegative("path_margin_m", c.path_margin_m);
  check.nonNegative("start_jitter.position_m", c.start_jitter.position_m);
  if (c.start_jitter.yaw_deg < 0.0 || c.start_jitter.yaw_deg > 180.0)
    check.fail("start_jitter.yaw_deg", "must be in [0, 180]", c.start_jitter.yaw_deg);
}

void validateRobot(const Checker& check, const RobotConfig& r) {
  check.positive("robot.radius_left_m", r.geometry.radius_left_m);
  check.positive("robot.radius_right_m", r.geometry.radius_right_m);
  check.positive("robot.wheel_base_m", r.geometry.wheel_base_m);
  check.positive("robot.wheel_width_m", r.wheel_width_m);
  check.positive("robot.wheel_mass_kg", r.wheel_mass_kg);
  check.positive("robot.chassis_mass_kg", r.chassis_mass_kg);
  check.positive("robot.max_wheel_torque_nm", r.max_wheel_torque_nm);
  check.nonNegative("robot.wheel_friction", r.wheel_friction);
  check.positive("robot.caster_radius_m", r.caster_radius_m);
  check.nonNegative("robot.caster_friction", r.caster_friction);
  check.positive("robot.chassis_length_m", r.chassis_length_m);
  check.positive("robot.chassis_width_m", r.chassis_width_m);
  check.positive("robot.chassis_height_m", r.chassis_height_m);
  check.nonNegative("robot.chassis_clearance_m", r.chassis_clearance_m);
  check.positive("robot.caster_offset_m", r.caster_offset_m);
  if (r.chassis_width_m >= r.geometry.wheel_base_m - r.wheel_width_m) {
    check.fail("robot.chassis_width_m", "must be less than wheel_base_m - wheel_width_m",
               r.chassis_width_m);
  }
}

/// The geometry odometry believes must stay positive: each relative error > -1.
void validateNominal(const Checker& check, const SimConfig& c) {
  if (!(c.nominal.radius_left_error > -1.0)) {
    check.fail("nominal.radius_left_error", "must be greater than -1", c.nominal.radius_left_error);
  }
  if (!(c.nominal.radius_right_error > -1.0)) {
    check.fail("nominal.radius_right_error", "must be greater than -1",
               c.nominal.radius_right_error);
  }
  if (!(c.nominal.wheel_base_error > -1.0)) {
    check.fail("nominal.wheel_base_error", "must be greater than -1", c.nominal.wheel_base_error);
  }
}

void validateLidar(const Checker& check, const LidarConfig& l) {
  check.positive("lidar.rate_hz", l.rate_hz);
  // Spinning 2D lidars turn at 5-50 Hz; 1e9 Hz used to end in bad_alloc (docs/simulate.md).
  if (l.rate_hz > kMaxLidarRate_hz)
    check.fail("lidar.rate_hz", "must be at most " + std::to_string(int(kMaxLidarRate_hz)),
               l.rate_hz);
  // A revolution longer than the scans' period would overlap the next scan's.
  if (!(l.sweep_s >= 0.0 && l.sweep_s <= 1.0 / l.rate_hz * (1.0 + 1e-9)))
    check.fail("lidar.sweep_s", "must be in [0, 1 / lidar.rate_hz] (0: 1 / lidar.rate_hz)",
               l.sweep_s);
  // Real 2D lidars have up to a few thousand beams; 1e6 would be 1e7 ray casts per second.
  if (l.beams_per_revolution < 1 || l.beams_per_revolution > 100000) {
    check.fail("lidar.beams_per_revolution", "must be between 1 and 100000",
               l.beams_per_revolution);
  }
  if (!(l.fov_rad > 0.0 && l.fov_rad <= 2.0 * std::numbers::pi + 1e-12)) {
    check.fail("lidar.fov_rad", "must be in (0, 2 pi]", l.fov_rad);
  }
  if (std::lround(l.beams_per_revolution * l.fov_rad / (2.0 * std::numbers::pi)) < 1) {
    check.fail("lidar.fov_rad", "covers less than one beam", l.fov_rad);
  }
  check.nonNegative("lidar.range_min_m", l.range_min_m);
  if (!(l.range_max_m > l.range_min_m)) {
    check.fail("lidar.range_max_m", "must exceed lidar.range_min_m", l.range_max_m);
  }
  check.nonNegative("lidar.range_noise_m", l.range_noise_m);
  check.nonNegative("lidar.range_noise_fixed_m", l.range_noise_fixed_m);
  check.positive("lidar.range_noise_fixed_length_m", l.range_noise_fixed_length_m);
  if (std::string error; !parseRangeBias(l.range_bias_by_beam_m, &error))
    check.fail("lidar.range_bias_by_beam_m", "expected comma-separated metres: " + error,
               l.range_bias_by_beam_m);
  if (std::string error; !parseRangeBias(l.range_bias_by_range_m, &error))
    check.fail("lidar.range_bias_by_range_m", "expected comma-separated metres: " + error,
               l.range_bias_by_range_m);
  if (!(l.range_noise_correlation >= 0.0 && l.range_noise_correlation < 1.0))
    check.fail("lidar.range_noise_correlation", "must be in [0, 1)", l.range_noise_correlation);
  check.positive("lidar.height_m", l.height_m);
}

/// Encoders and IMU.
void validateSensors(const Checker& check, const SimConfig& c) {
  if (c.encoders.ticks_per_revolution < 1) {
    check.fail("encoders.ticks_per_revolution", "must be at least 1",
               c.encoders.ticks_per_revolution);
  }
  check.positive("encoders.rate_hz", c.encoders.rate_hz);
  // A slip of half the wheel's turning is no longer odometry.
  if (!(c.encoders.slip_sigma >= 0.0 && c.encoders.slip_sigma <= kMaxSlipSigma))
    check.fail("encoders.slip_sigma", "must be in [0, 0.5]", c.encoders.slip_sigma);
  check.positive("encoders.slip_tau_s", c.encoders.slip_tau_s);
  if (!(c.encoders.turn_slip_sigma >= 0.0 && c.encoders.turn_slip_sigma <= kMaxSlipSigma))
    check.fail("encoders.turn_slip_sigma", "must be in [0, 0.5]", c.encoders.turn_slip_sigma);
  if (!(c.encoders.common_slip_sigma >= 0.0 && c.encoders.common_slip_sigma <= kMaxSlipSigma))
    check.fail("encoders.common_slip_sigma", "must be in [0, 0.5]", c.encoders.common_slip_sigma);
  check.positive("imu.rate_hz", c.imu.rate_hz);
  // Wheel encoders and IMUs are logged at up to a few kHz.
  if (c.encoders.rate_hz > kMaxSensorRate_hz)
    check.fail("encoders.rate_hz", "must be at most " + std::to_string(int(kMaxSensorRate_hz)),
               c.encoders.rate_hz);
  if (c.imu.rate_hz > kMaxSensorRate_hz)
    check.fail("imu.rate_hz", "must be at most " + std::to_string(int(kMaxSensorRate_hz)),
               c.imu.rate_hz);
  check.nonNegative("imu.gyro_noise_radps", c.imu.gyro_noise_radps);
  check.nonNegative("imu.accel_noise_mps2", c.imu.accel_noise_mps2);
}

void validatePeople(const Checker& check, const PeopleConfig& p) {
  // Every person is cast against every beam: a crowd would be a world, not a disturbance.
  if (!(p.count >= 0 && p.count <= 20)) check.fail("people.count", "must be in [0, 20]", p.count);
  check.positive("people.distance_m", p.distance_m);
  check.positive("people.correlation_s", p.correlation_s);
  if (!(p.radius_m > 0.0 && p.radius_m <= 1.0))
    check.fail("people.radius_m", "must be in (0, 1]", p.radius_m);
}

}  // namespace

void validate(const SimConfig& c, const std::string& where) {
  const Checker check{where};
  validateRun(check, c);
  validateRobot(check, c.robot);
  validateNominal(check, c);
  validateLidar(check, c.lidar);
  validateSensors(check, c);
  validateFaults(check, c.faults);
  validatePeople(check, c.people);
}

void checkRunSize(const SimConfig& c, double duration_s) {
  const auto refuse = [&](const std::string& keys, double count, double limit) {
    if (count <= limit) return;
    std::ostringstream msg;
    msg << "a run of " << duration_s << " s would take " << count << " samples, more than " << limit
        << ": lower the rate or the duration";
    throw InputError(keys, msg.str());
  };
  refuse("physics_rate_hz", duration_s * c.physics_rate_hz, kMaxSamples);
  refuse("encoders.rate_hz", duration_s * c.encoders.rate_hz, kMaxSamples);
  refuse("imu.rate_hz", duration_s * c.imu.rate_hz, kMaxSamples);
  refuse("lidar.rate_hz x lidar.beams_per_revolution",
         duration_s * c.lidar.rate_hz * c.lidar.beams_per_revolution, kMaxBeams);
}

double footprintRadius(const RobotConfig& r) {
  const double wheel_y = 0.5 * (r.geometry.wheel_base_m + r.wheel_width_m);
  const double wheel_x = std::max(r.geometry.radius_left_m, r.geometry.radius_right_m);
  return std::max({std::hypot(0.5 * r.chassis_length_m, 0.5 * r.chassis_width_m),
                   std::hypot(wheel_x, wheel_y), r.caster_offset_m + r.caster_radius_m});
}

}  // namespace slamprep::sim
