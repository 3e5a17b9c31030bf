#include "slamprep/eval/bench/twin.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "slamprep/algo/agreement/dataset_sources.hpp"
#include "slamprep/algo/agreement/sensor_agreement.hpp"
#include "slamprep/algo/matching/keyframe_odometry.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/bench/trajectory_smoother.hpp"
#include "slamprep/eval/bench/transient_returns.hpp"
#include "slamprep/eval/bench/twin_odometry.hpp"
#include "slamprep/eval/bench/twin_slip.hpp"
#include "slamprep/eval/metrics/error_stats.hpp"
#include "slamprep/eval/pipeline/calibration_run.hpp"
#include "slamprep/eval/pipeline/match_trajectory.hpp"
#include "slamprep/sim/drive/simulator.hpp"
#include "slamprep/sim/physics/planar_caster.hpp"

namespace slamprep::eval {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

/// Each of x, y and yaw of the calibrated mount replaces the told one where it departs from it
/// by more than this many of its sigmas (p < 0.003 for each, were the told one right).
constexpr double kMountSigmas = 3.0;

/// What the twin's lidar is mounted at: the recording's told mount, each component replaced by
/// the calibrated one where the scans and wheels show it wrong. ACES is told 0 and its scans and
/// wheels say 52 +- 5 mm ahead: driven as told, its twin turned 23 % more than its robot at the
/// scans' rate, zigzagging after the lidar's sideways swing in turns.
SE2 twinMount(const SE2& told, const algo::CalibrationResult& r, nlohmann::ordered_json& how) {
  const Eigen::VectorXd sigma = r.sigma();
  if (!r.estimates_mount || sigma.size() < 6) return told;
  const Eigen::Vector3d d(r.T_base_lidar.x - told.x, r.T_base_lidar.y - told.y,
                          normalizeAngle(r.T_base_lidar.yaw - told.yaw));
  Eigen::Vector3d m(told.x, told.y, told.yaw);
  for (int i = 0; i < 3; ++i)
    if (std::abs(d(i)) > kMountSigmas * sigma(3 + i)) m(i) += d(i);
  how = {{"calibrated",
          {{"x", r.T_base_lidar.x}, {"y", r.T_base_lidar.y}, {"yaw", r.T_base_lidar.yaw}}},
         {"sigma", {{"x", sigma(3)}, {"y", sigma(4)}, {"yaw", sigma(5)}}}};
  return SE2(m(0), m(1), normalizeAngle(m(2)));
}

struct TrueRobot {
  DiffDriveParams geometry;
  SE2 T_base_lidar;
  nlohmann::ordered_json how;        ///< where the geometry came from
  nlohmann::ordered_json mount_how;  ///< the calibrated mount and its sigma, where calibrated
};

/// The twin's true geometry and mount: given, calibrated from the recording, or the nominal one
/// (with the told mount).
TrueRobot trueRobot(const Dataset& real, const std::string& name, const TwinParams& p) {
  TrueRobot t{real.info.nominal_geometry, real.info.T_base_lidar, {}, nullptr};
  if (p.true_geometry) {
    t.how = {{"from", "given (--calibration)"}};
    t.geometry = *p.true_geometry;
    return t;
  }
  if (!p.calibrate) {
    t.how = {{"from", "nominal (no calibration asked)"}};
    return t;
  }
  const DatasetCalibration cal = calibrateForTwin(name, real);
  if (cal.runs.empty() || !cal.runs.front().result.ok) {
    t.how = {{"from", "nominal: calibration refused"},
             {"reason", cal.runs.empty() ? "no run" : cal.runs.front().result.reason}};
    return t;
  }
  const algo::CalibrationResult& r = cal.runs.front().result;
  const Eigen::VectorXd sigma = r.sigma();
  t.how = {{"from", kTwinCalibrationFlags},
           {"sigma_m", {sigma(0), sigma(1), sigma(2)}},
           {"intervals", r.intervals_used}};
  t.geometry = r.geometry;
  t.T_base_lidar = twinMount(real.info.T_base_lidar, r, t.mount_how);
  return t;
}

/// T_world_base of a base whose lidar mount is `to` instead of `from`, the lidar's path kept.
PoseSeries movedBase(const PoseSeries& T_world_base, const SE2& from, const SE2& to) {
  const SE2 T_from_to = from * to.inverse();
  PoseSeries out;
  for (const auto& s : T_world_base.samples()) out.push_back(s.stamp_s, s.value * T_from_to);
  return out;
}

/// A robot of the recorded geometry: wheels 2 cm wide, a chassis between them.
sim::RobotConfig twinRobot(const DiffDriveParams& g) {
  sim::RobotConfig r;
  r.geometry = g;
  r.wheel_width_m = 0.02;
  // At most 0.4 m: the --set list sets it before the wheel base, against the default 0.5 m.
  r.chassis_width_m = std::clamp(g.wheel_base_m - r.wheel_width_m - 0.02, 0.02, 0.4);
  r.chassis_length_m = std::min(0.4, g.wheel_base_m);
  r.caster_offset_m = 0.4 * r.chassis_length_m;
  r.caster_radius_m = std::min(0.03, 0.5 * std::min(g.radius_left_m, g.radius_right_m));
  r.chassis_clearance_m = std::min(0.04, 0.5 * std::min(g.radius_left_m, g.radius_right_m));
  return r;
}

}  // namespace

namespace {

/// The path of the kinematic replay, sampled at most `spacing_m` apart.
std::vector<Eigen::Vector2d> pathSamples(const PoseSeries& replay, double spacing_m) {
  std::vector<Eigen::Vector2d> out;
  for (std::size_t i = 0; i < replay.size(); ++i) {
    const Eigen::Vector2d b = replay[i].value.translation();
    if (!out.empty()) {
      const Eigen::Vector2d a = out.back();
      const int n = static_cast<int>(std::ceil((b - a).norm() / spacing_m));
      for (int s = 1; s < n; ++s) out.push_back(a + (b - a) * (double(s) / n));
    }
    out.push_back(b);
  }
  return out;
}

/// The pieces of the wall a -> b farther than `reach` (plus half its thickness) from every
/// path sample: map geometry the recorded robot drove through (a person walking, a door that
/// opened, a matching error) is cut away so the twin can drive where the robot did.
std::vector<std::pair<double, double>> clearPieces(const sim::Wall& w,
                                                   const std::vector<Eigen::Vector2d>& path,
                                                   double reach) {
  const Eigen::Vector2d d = (w.to_m - w.from_m).normalized();
  const Eigen::Vector2d n(-d.y(), d.x());
  const double length = (w.to_m - w.from_m).norm(), r = reach + 0.5 * w.thickness_m;
  std::vector<std::pair<double, double>> blocked;
  for (const Eigen::Vector2d& c : path) {
    const double h = std::abs((c - w.from_m).dot(n));
    if (h >= r) continue;
    const double u = (c - w.from_m).dot(d), half = std::sqrt(r * r - h * h);
    if (u + half > 0.0 && u - half < length) blocked.push_back({u - half, u + half});
  }
  std::sort(blocked.begin(), blocked.end());
  std::vector<std::pair<double, double>> free;
  double at = 0.0;
  for (const auto& [lo, hi] : blocked) {
    if (lo > at) free.push_back({at, lo});
    at = std::max(at, hi);
  }
  if (at < length) free.push_back({at, length});
  return free;
}

struct WorldBuild {
  sim::World world;
  int walls_cut = 0;  ///< walls (or clutter) the robot's path crossed, cut into pieces or removed
  int posts_removed = 0;
};

/// The map's faces as walls whose centre lies half a thickness behind the face, cut away where
/// the robot drove, and its posts as cylinders.
WorldBuild buildWorld(const WallMap& map, const WallExtractionParams& wp, const TrackedDrive& drive,
                      double reach_m) {
  WorldBuild b;
  b.world.name = "twin";
  b.world.T_world_start = drive.replay[0].value;
  const std::vector<Eigen::Vector2d> path = pathSamples(drive.replay, 0.02);
  auto add = [&](const WallSegment& s) {
    const sim::Wall w = faceAsWall(s, wp);
    const auto pieces = clearPieces(w, path, reach_m);
    const Eigen::Vector2d d = (w.to_m - w.from_m).normalized();
    if (pieces.size() != 1 || pieces[0].second - pieces[0].first < (w.to_m - w.from_m).norm())
      ++b.walls_cut;
    for (const auto& [lo, hi] : pieces)
      if (hi - lo >= wp.cell_m)
        b.world.walls.push_back({w.from_m + lo * d, w.from_m + hi * d, wp.thickness_m, 2.0, true});
  };
  for (const WallSegment& s : map.walls) add(s);
  for (const WallSegment& s : map.clutter) add(s);
  for (const Post& p : map.posts) {
    const bool hit = std::any_of(path.begin(), path.end(), [&](const Eigen::Vector2d& c) {
      return (c - p.center_m).norm() < reach_m + p.radius_m;
    });
    if (hit)
      ++b.posts_removed;
    else
      b.world.cylinders.push_back({p.center_m, p.radius_m, 1.0, true});
  }
  return b;
}

}  // namespace

namespace {

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);  // exact: 2 pi must stay <= 2 pi
  return buf;
}

/// "1,0.5,0": numbers to 4 significant digits, as the simulator's list keys read them
/// (faults.dropped_beams.by_angle, lidar.range_bias_by_beam_m: core/number_list.hpp).
std::string factors(const std::vector<double>& values) {
  std::string out;
  char buf[32];
  for (const double v : values) {
    std::snprintf(buf, sizeof buf, "%.4g", v);
    if (!out.empty()) out += ',';
    out += buf;
  }
  return out;
}

struct Fitted {
  LidarLayout layout;
  LidarAgainstMap against_map;
  OdometryFit odometry;
  WheelSlipFit slip;  ///< from the recording; the twin's sigma is set after its first run
  DiffDriveParams true_geometry;
  DiffDriveParams nominal;
  SE2 T_base_lidar;       ///< the twin's lidar mount (twinMount)
  SE2 told_T_base_lidar;  ///< the recording's, which the twin's dataset is told
  nlohmann::ordered_json mount_how;
  double fixed_share = 0.0;  ///< TwinFit::range_noise_fixed_share
  double scan_lag_s = 0.0;   ///< the scans' stamps behind the wheels' (what the clock sync moves)
  bool lag_measured = false;
  /// (r_R / b, r_L / b) that turn the wheels as the scans turned (sensor agreement, Eq. 1).
  std::optional<Eigen::Vector2d> turn_ratios;
  sim::RobotConfig robot;
};

/// The faults that reproduce the recording's glitches, appended to `s` with faults.enable last.
void faultSets(const Fitted& f, std::vector<std::string>& s) {
  std::vector<std::string> faults;
  if (f.against_map.twin_dropout_probability > 0.0) {
    faults.push_back("dropped_beams");
    s.push_back("faults.dropped_beams.probability=" + num(f.against_map.twin_dropout_probability));
    s.push_back("faults.dropped_beams.by_angle=" +
                factors(f.against_map.keep_factor_by_twin_angle));
    s.push_back("faults.dropped_beams.by_range=" + factors(f.against_map.keep_factor_by_range));
    s.push_back("faults.dropped_beams.range_bin_m=" + num(LidarMapParams{}.range_bin_m));
  }
  if (f.lag_measured && std::abs(f.scan_lag_s) >= 0.02) {
    faults.push_back("clock_offset");
    s.push_back("faults.clock_offset.offset_s=" + num(std::clamp(f.scan_lag_s, -1.0, 1.0)));
  }
  const OdometryFit& o = f.odometry;
  if (o.encoders_jitter_s > 0.0 || o.imu_jitter_s > 0.0 || o.scans_jitter_s > 0.0 ||
      o.encoders_sampling_jitter_s > 0.0) {
    faults.push_back("stamp_jitter");
    s.push_back("faults.stamp_jitter.sigma_s=0");
    s.push_back("faults.stamp_jitter.encoders_sigma_s=" + num(o.encoders_jitter_s));
    s.push_back("faults.stamp_jitter.imu_sigma_s=" + num(o.imu_jitter_s));
    s.push_back("faults.stamp_jitter.scans_sigma_s=" + num(o.scans_jitter_s));
    if (o.encoders_sampling_jitter_s > 0.0)
      s.push_back("faults.stamp_jitter.encoders_sampling_sigma_s=" +
                  num(o.encoders_sampling_jitter_s));
  }
  if (f.odometry.gaps > 0 && f.odometry.duration_s > 0.0) {
    faults.push_back("encoder_dropouts");
    s.push_back("faults.encoder_dropouts.rate_hz=" +
                num(double(f.odometry.gaps) / f.odometry.duration_s));
    s.push_back("faults.encoder_dropouts.duration_s=" + num(f.odometry.gap_mean_s));
  }
  std::string enable = "faults.enable=none";
  for (std::size_t i = 0; i < faults.size(); ++i)
    enable = (i == 0 ? "faults.enable=" : enable + ",") + faults[i];
  s.push_back(enable);
}

/// Beyond, the scans would share all their range error: none left to be drawn afresh.
constexpr double kMaxFixedShare = 0.99;

/// The range noise of total sigma split by `fixed_share` of its variance into the part drawn
/// afresh every scan (lidar.range_noise_m) and the part fixed in the world
/// (lidar.range_noise_fixed_m).
struct RangeNoiseSplit {
  double fresh_m, fixed_m;
};

RangeNoiseSplit splitRangeNoise(double sigma, double fixed_share) {
  return {sigma * std::sqrt(1.0 - fixed_share), sigma * std::sqrt(fixed_share)};
}

/// The total sigma of a lidar's range noise: its two parts are independent.
double totalRangeNoise(const sim::LidarConfig& l) {
  return std::hypot(l.range_noise_m, l.range_noise_fixed_m);
}

/// The recording's revolution, time_increment x beams per revolution, where it is shorter than
/// the scans' period (the head turns faster than scans are published); else 0, the period.
double twinSweep(const LidarLayout& l) {
  const double sweep_s = l.time_increment_s * l.beams_per_revolution;
  return sweep_s > 0.0 && l.rate_hz > 0.0 && sweep_s < 0.99 / l.rate_hz ? sweep_s : 0.0;
}

/// The simulator settings that reproduce the fit, as `--set` assignments in order.
std::vector<std::string> twinSets(const Fitted& f, std::uint64_t seed) {
  const DiffDriveParams& g = f.true_geometry;
  const sim::RobotConfig& r = f.robot;
  const LidarLayout& l = f.layout;
  const double sweep_s = twinSweep(l);
  std::vector<std::string> s = {
      "seed=" + std::to_string(seed),
      // The chassis first: each assignment is checked, and it must fit between the wheels.
      "robot.wheel_width_m=" + num(r.wheel_width_m),
      "robot.chassis_width_m=" + num(r.chassis_width_m),
      "robot.chassis_length_m=" + num(r.chassis_length_m),
      "robot.caster_offset_m=" + num(r.caster_offset_m),
      "robot.caster_radius_m=" + num(r.caster_radius_m),
      "robot.chassis_clearance_m=" + num(r.chassis_clearance_m),
      "robot.radius_left_m=" + num(g.radius_left_m),
      "robot.radius_right_m=" + num(g.radius_right_m), "robot.wheel_base_m=" + num(g.wheel_base_m),
      "nominal.radius_left_error=" + num(f.nominal.radius_left_m / g.radius_left_m - 1.0),
      "nominal.radius_right_error=" + num(f.nominal.radius_right_m / g.radius_right_m - 1.0),
      "nominal.wheel_base_error=" + num(f.nominal.wheel_base_m / g.wheel_base_m - 1.0),
      "lidar.rate_hz=" + num(l.rate_hz),
      "lidar.beams_per_revolution=" + std::to_string(l.beams_per_revolution),
      "lidar.sweep_s=" + num(sweep_s),
      std::string("lidar.free_running=") + (sweep_s > 0.0 ? "true" : "false"),
      "lidar.fov_rad=" + num(l.fov_rad),
      std::string("lidar.clockwise=") + (l.angle_increment_rad < 0.0 ? "true" : "false"),
      "lidar.range_min_m=" + num(l.range_min_m), "lidar.range_max_m=" + num(l.usable_max_m),
      "lidar.mount.x_m=" + num(f.T_base_lidar.x), "lidar.mount.y_m=" + num(f.T_base_lidar.y),
      "lidar.mount.yaw_rad=" + num(normalizeAngle(f.T_base_lidar.yaw + l.mount_yaw_shift_rad)),
      "nominal.lidar_mount_error.x_m=" + num(f.told_T_base_lidar.x - f.T_base_lidar.x),
      "nominal.lidar_mount_error.y_m=" + num(f.told_T_base_lidar.y - f.T_base_lidar.y),
      "nominal.lidar_mount_error.yaw_rad=" +
          num(normalizeAngle(f.told_T_base_lidar.yaw - f.T_base_lidar.yaw)),
      "encoders.rate_hz=" + num(f.odometry.encoder_rate_hz),
      "encoders.ticks_per_revolution=" + std::to_string(f.odometry.ticks_per_revolution),
      "encoders.slip_tau_s=" + num(f.slip.tau_s)};
  const RangeNoiseSplit noise = splitRangeNoise(f.against_map.range_noise_m, f.fixed_share);
  s.push_back("lidar.range_noise_m=" + num(noise.fresh_m));
  if (noise.fixed_m > 0.0) s.push_back("lidar.range_noise_fixed_m=" + num(noise.fixed_m));
  if (!f.against_map.range_bias_by_beam_m.empty())
    s.push_back("lidar.range_bias_by_beam_m=" + factors(f.against_map.range_bias_by_beam_m));
  if (f.odometry.has_imu && f.odometry.gyro_noise_radps > 0.0) {
    s.push_back("imu.rate_hz=" + num(f.odometry.imu_rate_hz));
    s.push_back("imu.gyro_bias_radps=" + num(f.odometry.gyro_bias_radps));
    s.push_back("imu.gyro_noise_radps=" + num(f.odometry.gyro_noise_radps));
  }
  faultSets(f, s);
  return s;
}

/// The delay of the scans behind the wheels: what the clock sync moves (eval::syncOntoScans, as
/// `calibrate --sync auto` does: measured, moved, and what is left measured again), on a copy.
void measureLag(const Dataset& real, const PoseSeries& scan_only, const std::string& deskew,
                Fitted& f) {
  const algo::SensorAgreement a = scanAgreement(real, scan_only);
  const algo::PairAgreement* p = algo::wheelsAgainstScans(a);
  if (!p || p->kept == 0) return;
  f.turn_ratios = p->wheel_ratios;
  Dataset synced = real;
  f.scan_lag_s = syncOntoScans(synced, a, deskew, false);
  f.lag_measured = true;
}

}  // namespace

namespace {

nlohmann::ordered_json fitted(nlohmann::ordered_json value, const std::string& how) {
  return {{"value", std::move(value)}, {"how", how}};
}

/// The lidar's layout as the recording's scans state it.
nlohmann::ordered_json layoutJson(const LidarLayout& l) {
  return {
      {"rate_hz",
       fitted(
           l.rate_hz,
           "1 / the scan stamps' period: their grid's where they have one, else the median step")},
      {"beams_per_scan", fitted({{"mean", l.beams_per_scan_mean},
                                 {"min", l.beams_min},
                                 {"max", l.beams_max},
                                 {"most_common", l.beams_mode}},
                                "counted per scan; the twin has one count, beams_per_revolution "
                                "x fov / 2 pi")},
      {"angle_min_deg", fitted(l.angle_min_rad * kDegPerRad, "of the most common layout")},
      {"angle_increment_deg",
       fitted(l.angle_increment_rad * kDegPerRad, "median; negative: clockwise")},
      {"beams_per_revolution", fitted(l.beams_per_revolution, "round(360 deg / |increment|)")},
      {"fov_deg", fitted(l.fov_rad * kDegPerRad, "most common count x increment, at most 360")},
      {"mount_yaw_shift_deg", fitted(l.mount_yaw_shift_rad * kDegPerRad,
                                     "added to the mount's yaw so the twin's beam i points "
                                     "where the recorded beam i did")},
      {"time_increment_s",
       fitted(l.time_increment_s,
              "median of the scans' time_increment; the twin's is sweep_s / beams_per_revolution")},
      {"sweep_s", fitted(twinSweep(l),
                         "time_increment x beams_per_revolution where shorter than the scans' "
                         "period (the head turns faster than scans are published), else 0: "
                         "the twin's lidar.sweep_s")},
      {"stamp", fitted("first beam", "the dataset's convention (docs/dataset.md); the twin's too")},
      {"range_min_m", fitted(l.range_min_m, "median of the scans' range_min")},
      {"range_max_m", fitted(l.range_max_m, "median of the scans' range_max")},
      {"usable_max_range_m", fitted(l.usable_max_m, "the longest valid reading")},
      {"no_return_fraction", fitted(l.no_return_fraction, "invalid beams of all beams")}};
}

/// What the recording's scans measure against the twin's world: noise, drops, their pattern.
nlohmann::ordered_json againstMapJson(const LidarAgainstMap& m) {
  return {
      {"range_noise_m", fitted(m.range_noise_m,
                               "1.4826 MAD of measured - cast range of the "
                               "accepted scans in the twin's world; includes the "
                               "walls' fit and the matched poses' error")},
      {"residual_median_m", fitted(m.residual_median_m, "signed median of the same residuals")},
      {"residual_neighbour_correlation",
       fitted(m.residual_neighbour_correlation,
              "robust correlation of neighbouring beams' residuals (docs/twin.md, Lidar)")},
      {"residual_beam_halves_correlation",
       fitted(m.residual_beam_halves_correlation,
              "each beam's mean residual over the first half of the scans against its mean over "
              "the second, correlated over the beams: a range error fixed in the lidar's frame "
              "repeats by beam wherever the robot is, the world's shape does not")},
      {"range_bias_by_beam_m",
       fitted(m.range_bias_by_beam_m,
              "each beam's mean residual less the mean over the beams, times sqrt(2 rho / (1 + "
              "rho)), the square root of a mean over both halves' reliability (rho: "
              "residual_beam_halves_correlation), so the pattern has the variance of the beams' "
              "own error; where rho is beyond 3 / sqrt(beams) and 0.25 (chance: neighbouring "
              "beams' means move together with the world's shape), else none; none too where "
              "its RMS exceeds the recording's whole residual (range_bias_not_given): the "
              "twin's lidar.range_bias_by_beam_m")},
      {"range_bias_not_given", m.range_bias_not_given.empty()
                                   ? nlohmann::ordered_json(nullptr)
                                   : nlohmann::ordered_json(m.range_bias_not_given)},
      {"residuals", m.residuals},
      {"dropout_probability", fitted(m.dropout_probability,
                                     "no return where the world predicts one within the usable "
                                     "range")},
      {"escape_fraction", fitted(m.escape_fraction,
                                 "beams for which the world predicts no wall within the usable "
                                 "range: the twin returns nothing there")},
      {"twin_dropout_probability",
       fitted(m.twin_dropout_probability,
              "(no-return fraction within the usable range - escape_fraction) / (1 - "
              "escape_fraction): the twin drops beams at this mean rate, so that its "
              "escapes and drops together make the recording's no-returns; shaped by "
              "keep_factor_by_twin_angle and keep_factor_by_range")},
      {"spurious_fraction", fitted(m.spurious_fraction,
                                   "a return where the world predicts none "
                                   "(people, what the walls missed)")},
      {"dropout_by_angle", fitted(m.dropout_by_angle, "per 10 deg of beam angle from -180")},
      {"dropout_by_range", fitted(m.dropout_by_range, "per 0.5 m of predicted range from 0")},
      {"keep_factor_by_twin_angle",
       fitted(m.keep_factor_by_twin_angle,
              "keep(angle, range) = (1 - twin_dropout_probability) x this x "
              "keep_factor_by_range, fitted to the returns of every (10 deg, 0.5 m) bin with its "
              "drops scaled by twin_dropout_probability / dropout_probability; per 10 deg of the "
              "twin's beam angle from -180 (the recorded angle minus mount_yaw_shift_deg): the "
              "twin's faults.dropped_beams.by_angle")},
      {"keep_factor_by_range",
       fitted(m.keep_factor_by_range,
              "the same per 0.5 m of predicted range: the twin's faults.dropped_beams.by_range")}};
}

nlohmann::ordered_json lidarJson(const Fitted& f) {
  nlohmann::ordered_json j = layoutJson(f.layout);
  const nlohmann::ordered_json against_map = againstMapJson(f.against_map);  // outlives items()
  for (const auto& [key, value] : against_map.items()) j[key] = value;
  const auto pose = [](const SE2& m) {
    return nlohmann::ordered_json{{"x", m.x}, {"y", m.y}, {"yaw", m.yaw}};
  };
  nlohmann::ordered_json mount = {{"told", pose(f.told_T_base_lidar)},
                                  {"true", pose(f.T_base_lidar)}};
  if (f.mount_how.is_object())
    for (const auto& [key, value] : f.mount_how.items()) mount[key] = value;
  j["range_noise_fixed_share"] = fitted(f.fixed_share, "");  // simulateTwin tunes it
  j["mount"] = fitted(
      mount,
      "told: the recording's dataset.json, which the twin's is told too "
      "(nominal.lidar_mount_error); true: the twin's lidar.mount, the told one with each of "
      "x, y and yaw replaced by the calibration's (calibrated, its sigma) where that departs "
      "by more than " +
          num(kMountSigmas) + " sigmas; yaw before mount_yaw_shift_deg");
  return j;
}

/// "1.5, 3, 6 and 12 s": the pieces' durations as the fit cuts them.
std::string pieceDurations(const std::vector<double>& durations_s) {
  std::string out;
  char buf[32];
  for (std::size_t i = 0; i < durations_s.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%g", durations_s[i]);
    out += (i == 0 ? "" : i + 1 == durations_s.size() ? " and " : ", ") + std::string(buf);
  }
  return out + " s";
}

nlohmann::ordered_json slipJson(const WheelSlipFit& s) {
  return {
      {"sigma", s.fitted ? nlohmann::ordered_json(s.sigma) : nullptr},
      {"turn_sigma", s.fitted ? nlohmann::ordered_json(s.turn_sigma) : nullptr},
      {"tau_s", s.tau_s},
      {"pieces", s.pieces},
      {"timing_jitter_s", s.fitted ? nlohmann::ordered_json(s.timing_jitter_s) : nullptr},
      {"timing_likelihood_ratio",
       s.fitted ? nlohmann::ordered_json(s.timing_likelihood_ratio) : nullptr},
      {"reference_noise_rad", s.fitted ? nlohmann::ordered_json(s.reference_noise_rad) : nullptr},
      {"common_sigma", s.common_fitted ? nlohmann::ordered_json(s.common_sigma) : nullptr},
      {"common_likelihood_ratio",
       s.common_fitted ? nlohmann::ordered_json(s.common_likelihood_ratio) : nullptr},
      {"distance_pieces", s.distance_pieces},
      {"reference_distance_noise_m",
       s.common_fitted ? nlohmann::ordered_json(s.reference_distance_noise_m) : nullptr},
      {"how",
       "the recording's encoders with the true geometry, its r_L / b and r_R / b those of the "
       "sensor agreement (the turn the scans saw per wheel angle), against the scans matched "
       "alone (moved by scan_lag_s) over pieces of " +
           pieceDurations(WheelSlipParams{}.piece_s) +
           ": the squared heading error of a piece regressed on what Ornstein-Uhlenbeck slips "
           "of correlation time tau_s predict for its wheels' motion (sigma: each wheel counts "
           "(1 + s) of what it rolled) and for its turning (turn_sigma: the wheels count (1 + u) "
           "of the turn), for the turn rates at its ends (timing_jitter_s: the wheels read that "
           "far off the scans' time, independently per reading; 0 unless it raises the pieces' "
           "likelihood, each stretch counted once, by a ratio timing_likelihood_ratio beyond "
           "10.83, chi2(1) at p = 0.001), plus a constant (the matcher's "
           "own noise, reference_noise_rad); sigma, turn_sigma and timing_jitter_s: the "
           "recording's; the twin is given what its run without them, measured the same way "
           "against its own scans, does not show already (twin_sigma, physics_sigma; "
           "twin_turn_sigma, physics_turn_sigma; twin_read_jitter_s, physics_timing_jitter_s: "
           "faults.read_jitter). common_sigma: the slip both wheels share (they count (1 + c) "
           "of the distance, no heading), from the pieces that turn less than 30 deg: the "
           "distance the wheels count against the scans' chord, regressed on what such a slip "
           "predicts, with the wheel slip sigma held and the scans' own error (a constant, "
           "reference_distance_noise_m, and terms in the turn rate and the speed at the ends) "
           "beside it; the twin is given twin_common_sigma beyond physics_common_sigma"}};
}

/// The true geometry with the wheels' turn per wheel angle, r_L / b and r_R / b, the sensor
/// agreement's (Eq. 1): what no wheel geometry explains is the slip. A short recording's
/// calibration is loose (sigma of b 20-36 mm on the Neatos), and its wrong turn grows with the
/// wheels' motion as slip does: fsm_bag's slip fitted 0.048 with it, 0.012 with these.
DiffDriveParams turningGeometry(DiffDriveParams g, const std::optional<Eigen::Vector2d>& ratios) {
  if (!ratios) return g;
  g.radius_right_m = (*ratios)(0) * g.wheel_base_m;
  g.radius_left_m = (*ratios)(1) * g.wheel_base_m;
  return g;
}

/// What a dataset's random wheel slip is fitted on: its wheels against its scans matched alone,
/// moved to the wheels' clock by the scans' lag (a lag would otherwise look like slip in turns).
WheelSlipInput slipAgainstScans(const Dataset& d, const std::string& name,
                                const PoseSeries& scan_only, const DiffDriveParams& geometry,
                                double lag_s) {
  PoseSeries accepted;
  for (const auto& s : scan_only.samples()) accepted.push_back(s.stamp_s - lag_s, s.value);
  return {odometryEncoders(d, name), geometry, std::move(accepted)};
}

WheelSlipInput recordingSlipInput(const Dataset& real, const std::string& name,
                                  const PoseSeries& scan_only, const Fitted& f) {
  return slipAgainstScans(real, name, scan_only, turningGeometry(f.true_geometry, f.turn_ratios),
                          f.lag_measured ? f.scan_lag_s : 0.0);
}

nlohmann::ordered_json odometryJson(const Fitted& f, const nlohmann::ordered_json& geometry_how) {
  const OdometryFit& o = f.odometry;
  auto g = [](const DiffDriveParams& p) {
    return nlohmann::ordered_json{{"radius_left_m", p.radius_left_m},
                                  {"radius_right_m", p.radius_right_m},
                                  {"wheel_base_m", p.wheel_base_m}};
  };
  nlohmann::ordered_json j = {
      {"nominal", fitted(g(f.nominal), "dataset.json: what the odometry is told")},
      {"true", fitted(g(f.true_geometry), geometry_how.value("from", ""))},
      {"calibration", geometry_how},
      {"rate_hz", fitted(o.encoder_rate_hz,
                         "1 / the encoder stamps' period: their grid's "
                         "where they have one, else the median step")},
      {"stamp_jitter_s",
       fitted({{"encoders", o.encoders_jitter_s},
               {"imu", o.imu_jitter_s},
               {"scans", o.scans_jitter_s},
               {"encoders_about_grid", o.encoders_grid_jitter_s},
               {"encoders_sampling", o.encoders_sampling_jitter_s},
               {"encoders_stamp_error_bound",
                o.encoders_stamp_error_bound_s
                    ? nlohmann::ordered_json(*o.encoders_stamp_error_bound_s)
                    : nlohmann::ordered_json(nullptr)}},
              "RMS of each stream's stamps about its grid where calibrate puts them back on it "
              "(docs/deskew.md \"Jittered stamps\"), else 0: the twin's "
              "faults.stamp_jitter; the encoders' at most what their ticks say the stamps can be "
              "wrong by (encoders_stamp_error_bound: ticks that follow irregular stamps were "
              "sampled irregularly, not stamped wrong), the rest of their jitter about the grid "
              "when they were sampled (encoders_sampling: "
              "faults.stamp_jitter.encoders_sampling_sigma_s; docs/twin.md \"Stamp jitter\")")},
      {"ticks_per_revolution", fitted(o.ticks_per_revolution, "dataset.json")},
      {"gaps", fitted({{"count", o.gaps}, {"mean_s", o.gap_mean_s}, {"max_s", o.gap_max_s}},
                      "encoder steps over 2.5 median steps: stale runs the import dropped, lost "
                      "samples; the twin drops samples at this rate (encoder_dropouts)")},
      {"scan_lag_s", fitted(f.lag_measured ? nlohmann::ordered_json(f.scan_lag_s) : nullptr,
                            "the clock sync of calibrate --sync auto on the scans matched alone: "
                            "the scans' stamps behind the wheels' (the twin's clock_offset when "
                            "at least 20 ms)")}};
  j["slip"] = slipJson(f.slip);
  j["gyro"] = o.has_imu ? nlohmann::ordered_json{{"rate_hz", o.imu_rate_hz},
                                                 {"still_samples", o.still_samples},
                                                 {"bias_radps", o.gyro_bias_radps},
                                                 {"noise_radps", o.gyro_noise_radps},
                                                 {"how", "mean and std where the wheels stood"}}
                        : nlohmann::ordered_json(nullptr);
  return j;
}

nlohmann::ordered_json worldJson(const WallMap& map, const WorldBuild& b) {
  return {{"how",
           "matched points in a 5 cm grid (cells with >= 2 returns), straight runs found "
           "by a Hough transform, fitted by total least squares, split at 0.25 m gaps; "
           "the rest as short walls and posts; geometry the robot's path crosses cut away"},
          {"occupied_cells", map.occupied_cells},
          {"cells_on_walls_percent",
           map.occupied_cells ? 100.0 * map.cells_on_walls / map.occupied_cells : 0.0},
          {"walls", map.walls.size()},
          {"short_walls", map.clutter.size()},
          {"posts", map.posts.size()},
          {"cut_by_the_path", b.walls_cut},
          {"posts_removed", b.posts_removed},
          {"world_walls", b.world.walls.size()},
          {"world_cylinders", b.world.cylinders.size()}};
}

/// The recording's transient returns as its world's transients: each a disc of the search's
/// radius whose near face is where the return was, there for half a scan period either side of
/// its beam's time on the drive's clock, so that the twin's lidar sees it once, from about where
/// the robot's did.
std::vector<sim::Transient> replayedTransients(const TransientReturns& found,
                                               const TransientParams& p, double period_s,
                                               double t0_s) {
  std::vector<sim::Transient> out;
  for (const TransientPoint& q : found.points) {
    const Eigen::Vector2d away = (q.p_world - q.origin_world).normalized();
    const double t = q.t_s - t0_s;
    out.push_back(
        {t - 0.5 * period_s, t + 0.5 * period_s, q.p_world + p.radius_m * away, p.radius_m});
  }
  return out;
}

nlohmann::ordered_json transientsJson(const TransientReturns& found, const TransientParams& p,
                                      double period_s) {
  return {{"returns", found.returns},
          {"transient", found.transient},
          {"fraction", found.fraction()},
          {"radius_m", p.radius_m},
          {"present_s", period_s},
          {"how",
           "the recording's returns (0.5 m to the usable range) that no return at least 3 s "
           "earlier or later lies within 5 cm of, placed by the map's matched trajectory (twin "
           "--compare's scan_transient_fraction): each replayed as a disc of 5 cm whose near "
           "face is where the return was, there for one scan period about its time "
           "(transients.csv, the world's transients_file): people walking by, things moved, "
           "clutter seen once"}};
}

nlohmann::ordered_json axisJson(const AxisNoise& a, double scale, const std::string& unit) {
  return {{"measurement_" + unit, a.measurement * scale},
          {"acceleration_psd_" + unit + "2_per_s3", a.acceleration_psd * scale * scale}};
}

nlohmann::ordered_json smoothingJson(const SmoothedTrajectory& s) {
  return {{"how",
           "the matched poses' x, y and yaw each smoothed by a constant-velocity Rauch-Tung-"
           "Striebel smoother, the white acceleration's density and the matches' white error "
           "fitted by maximum likelihood (innovations beyond 3 sigmas count linearly)"},
          {"x", axisJson(s.x, 1.0, "m")},
          {"y", axisJson(s.y, 1.0, "m")},
          {"yaw", axisJson(s.yaw, kDegPerRad, "deg")},
          {"rms_shift_m", s.rms_shift_m},
          {"rms_shift_deg", s.rms_shift_deg}};
}

nlohmann::ordered_json driveJson(const TrackedDrive& d, const SmoothedTrajectory& motion,
                                 const TrackParams& p, const sim::TrackingParams& t) {
  return {{"how",
           "commands: wheel rates every period_s (scenario type track) that a kinematic "
           "robot of the true geometry drives onto the matched trajectory, smoothed "
           "(smoothing); in physics mode "
           "they are the feed-forward of a closed loop that steers the true pose back onto "
           "that kinematic replay (Kanayama et al. 1990), so the physics' slip does not pile up"},
          {"closed_loop",
           {{"k_x_per_s", t.k_x_per_s},
            {"k_y_per_m2", t.k_y_per_m2},
            {"k_theta_per_m", t.k_theta_per_m},
            {"how",
             "v = v_r cos(e_theta) + k_x e_x, w = w_r + v_r (k_y e_y + k_theta sin(e_theta)), "
             "(e_x, e_y, e_theta) the replay's pose in the robot's frame; wheel rates capped at "
             "max_wheel_radps"}}},
          {"period_s", p.period_s},
          {"knots", d.wheel_rates.size()},
          {"max_wheel_radps", p.max_wheel_radps},
          {"ramp_s", p.ramp_s},
          {"distance_m", d.distance_m},
          {"replay_rms_position_m", d.rms_position_m},
          {"replay_max_position_m", d.max_position_m},
          {"replay_rms_heading_deg", d.rms_heading_deg},
          {"clamped_knots", d.clamped},
          {"smoothing", smoothingJson(motion)}};
}

const char* const kNotReproduced[] = {
    "the beam count varies only where the recording's does not: the twin has one count",
    "a no-return pattern in which angle and range interact: the twin's is the two's product",
    "twist spikes (import --json reports them; the dataset does not keep the twist)",
    ("slip whose size is not Gaussian (a few large heading errors beside many small ones): the "
     "twin's slips are Gaussian, fitted to their variance"),
    ("moving people and objects as objects: their returns are replayed one by one, each where "
     "and when it was seen (world.transients), not as something that walks on; what stood in "
     "the robot's path is cut from the world"),
    ("odometry sampled on a coarser internal clock (steps of 3 or 4 ticks): the twin's irregular "
     "sampling is Gaussian, fitted to its RMS about the grid"),
    ("range errors fixed in the world at scales other than 2 cm (clutter, curved surfaces): "
     "the twin's fixed part is one Gaussian texture of 2 cm correlation length "
     "(lidar.range_noise_fixed_share)")};

}  // namespace

TwinFit fitTwin(const Dataset& real, const std::string& name, const TwinParams& p) {
  if (real.scans.size() < 2) throw InputError(name, "needs at least two scans to make a twin");
  Fitted f;
  f.layout = fitLidarLayout(real);
  f.nominal = real.info.nominal_geometry;
  const MatchTrajectoryOptions options = twinMatchOptions();
  const ScanPoints points = matchScanPoints(real, p.deskew, false);
  const MatchTrajectory run = matchTrajectory(real, points, options);
  if (run.tracked.matched == 0) {
    const std::string cause =
        algo::sparseScansCause(run.tracked.sparse, run.tracked.scans.size() - 1);
    throw InputError(name, "no scan matched: no map to make a world of" +
                               (cause.empty() ? "" : " (" + cause + ")"));
  }
  std::vector<char> accepted;
  const WallMap map =
      extractWalls(matchedMapPoints(run, points.points, f.layout.usable_max_m, accepted), p.walls);
  const TrueRobot truth = trueRobot(real, name, p);
  const nlohmann::ordered_json& geometry_how = truth.how;
  f.true_geometry = truth.geometry;
  f.T_base_lidar = truth.T_base_lidar;
  f.told_T_base_lidar = real.info.T_base_lidar;
  f.mount_how = truth.mount_how;
  f.robot = twinRobot(f.true_geometry);
  f.odometry = fitOdometry(real);
  TrackParams track = p.track;  // as fast as the recorded wheels turned, with a margin
  if (f.odometry.wheel_rate_p99_radps > 0.0)
    track.max_wheel_radps =
        std::min(track.max_wheel_radps, p.wheel_rate_margin * f.odometry.wheel_rate_p99_radps);
  // The motion, not the matches' jitter: driven as matched, a TurtleBot4's twin changed speed
  // 13x more from knot to knot than its robot did (docs/twin.md "Drive").
  // The twin drives its wheels' path: where the recording's told mount is not its lidar's, the
  // matched "base" swings sideways in turns, which a diff drive can follow only by zigzagging.
  const SmoothedTrajectory motion =
      smoothTrajectory(movedBase(run.T_world_base, real.info.T_base_lidar, f.T_base_lidar));
  const TrackedDrive drive = trackTrajectory(motion.T_world_base, f.true_geometry, track);
  sim::SimConfig probe;
  probe.robot = f.robot;
  const double reach = sim::footprintRadius(f.robot) + probe.path_margin_m + p.path_clearance_m;
  WorldBuild built = buildWorld(map, p.walls, drive, reach);
  if (built.world.walls.empty() && built.world.cylinders.empty())
    throw InputError(name, "the matched map has no walls to make a world of");
  TransientParams moving;
  moving.keep_points = true;
  const TransientReturns found =
      transientReturns(real, run.T_world_base, accepted, f.layout.usable_max_m, moving);
  const double period_s = f.layout.rate_hz > 0.0 ? 1.0 / f.layout.rate_hz : 0.0;
  built.world.transients = replayedTransients(found, moving, period_s, drive.t0_s);
  const sim::PlanarCaster caster(built.world);
  f.against_map = compareWithMap(real, run.T_world_base, accepted, caster, f.layout, p.lidar);
  const PoseSeries scan_only = scanOnlyPoses(real, points, options, run);
  measureLag(real, scan_only, p.deskew, f);
  WheelSlipInput slip_input = recordingSlipInput(real, name, scan_only, f);
  f.slip = fitWheelSlip(slip_input);
  TwinFit out;
  out.recording_slip_input = std::move(slip_input);
  // The recording's vicp match is the one above where the twin matches with vicp (the default).
  const MatchedScans as_measured =
      p.deskew == "vicp" ? measureMatchedScans(real, points, run, f.layout, p.walls, p.lidar)
                         : measureMatchedScans(real, f.layout, p.walls, p.lidar);
  out.residual_median_m = as_measured.residual_median_m;
  dropBeamBiasBeyondResidual(as_measured.residual_median_m, f.against_map);
  out.residual_neighbour_correlation = as_measured.neighbour_correlation;
  f.fixed_share = std::clamp(as_measured.revisit_correlation, 0.0, kMaxFixedShare);
  out.range_noise_fixed_share = f.fixed_share;
  out.residual_revisit_correlation = as_measured.revisit_correlation;
  out.layout = f.layout;
  out.walls = p.walls;
  out.lidar = p.lidar;
  out.recording_slip = f.slip;
  out.deskew = p.deskew;
  out.replay = drive.replay;
  out.sets = twinSets(f, p.seed);
  for (const std::string& s : out.sets) sim::applyOverride(out.config, s);
  nlohmann::ordered_json world_json = worldJson(map, built);
  world_json["transients"] = transientsJson(found, moving, period_s);
  if (!built.world.transients.empty())
    out.transients_csv = sim::transientsCsv(built.world.transients);
  out.world = std::move(built.world);
  out.world_yaml = worldYaml(out.world, "The world of slamprep twin " + name + " (docs/twin.md)");
  out.scenario_yaml = scenarioYaml(drive, track, p.tracking,
                                   "The matched trajectory of " + name + " as wheel-rate commands");
  out.json = {{"dataset", name},
              {"match",
               {{"deskew", p.deskew},
                {"scans", run.tracked.scans.size()},
                {"matched", run.tracked.matched},
                {"accepted_for_the_map", std::count(accepted.begin(), accepted.end(), 1)}}},
              {"world", world_json},
              {"drive", driveJson(drive, motion, track, p.tracking)},
              {"lidar", lidarJson(f)},
              {"odometry", odometryJson(f, geometry_how)},
              {"not_reproduced", kNotReproduced},
              {"sets", out.sets}};
  return out;
}

namespace {

/// Sets `key` in the configuration and the --set list (replaced, else appended).
void setKey(TwinFit& fit, const std::string& key, const std::string& value) {
  const std::string set = key + "=" + value;
  sim::applyOverride(fit.config, set);
  auto it = std::find_if(fit.sets.begin(), fit.sets.end(),
                         [&](const std::string& s) { return s.rfind(key + "=", 0) == 0; });
  if (it == fit.sets.end())
    fit.sets.push_back(set);
  else
    *it = set;
  fit.json["sets"] = fit.sets;
}

/// The total sigma, split as the fit splits it (splitRangeNoise); the fixed part is set where
/// there is some or was some before.
void setRangeNoise(TwinFit& fit, double sigma) {
  const RangeNoiseSplit noise = splitRangeNoise(sigma, fit.range_noise_fixed_share);
  setKey(fit, "lidar.range_noise_m", num(noise.fresh_m));
  if (noise.fixed_m > 0.0 || fit.config.lidar.range_noise_fixed_m > 0.0)
    setKey(fit, "lidar.range_noise_fixed_m", num(noise.fixed_m));
  fit.json["lidar"]["range_noise_m"]["value"] = sigma;
}

/// Largest distance of the simulated truth from the kinematic replay at its knots.
double replayDeviation(const sim::SimResult& r, const PoseSeries& replay) {
  double worst = 0.0;
  for (const auto& knot : replay.samples())
    if (const auto T = r.dataset.groundtruth.at(knot.stamp_s))
      worst = std::max(worst, (T->translation() - knot.value.translation()).norm());
  return worst;
}

/// The first run; in kinematic mode again when the physics' robot leaves the replay.
sim::SimResult firstRun(TwinFit& fit, const sim::Scenario& scenario, sim::RecordedMotion& motion) {
  sim::SimResult r = sim::simulate(fit.config, fit.world, scenario, motion);
  nlohmann::ordered_json& drive = fit.json["drive"];
  drive["mode"] = "physics";
  if (fit.config.mode != sim::SimMode::physics) return r;
  const double deviation = replayDeviation(r, fit.replay);
  drive["physics_max_deviation_m"] = deviation;
  char limit[32];
  std::snprintf(limit, sizeof limit, "%g m", fit.max_physics_deviation_m);
  if (deviation <= fit.max_physics_deviation_m) {
    drive["mode_how"] = std::string("the physics' robot, driven in closed loop, stayed within ") +
                        limit + " of the kinematic replay";
    return r;
  }
  setKey(fit, "mode", "kinematic");
  drive["mode"] = "kinematic";
  drive["mode_how"] =
      std::string("the physics' robot left the kinematic replay by more than ") + limit +
      " although driven in closed loop (a robot that touches a wall stops; capped wheels "
      "cannot catch up): the commands are driven exactly (kinematic mode), the odometry errors "
      "are the nominal geometry's and the ticks'";
  return sim::simulate(fit.config, fit.world, scenario, motion);
}

}  // namespace

namespace {

/// Linear in the runs (setting, measured) that bracket `target`, else extrapolated past the
/// largest setting (at most to `cap`); the smallest setting where it measures past the target.
double secantStep(std::vector<std::pair<double, double>> runs, double target, double cap) {
  std::sort(runs.begin(), runs.end());
  if (target <= runs.front().second) return runs.front().first;
  for (std::size_t i = 1; i < runs.size(); ++i) {
    const auto [s0, r0] = runs[i - 1];
    const auto [s1, r1] = runs[i];
    if ((r0 - target) * (r1 - target) <= 0.0 && r1 != r0)
      return s0 + (target - r0) * (s1 - s0) / (r1 - r0);
  }
  const auto [s0, r0] = runs[runs.size() - 2];
  const auto [s1, r1] = runs.back();
  const double slope = (r1 - r0) / (s1 - s0);
  return slope > 0.0 ? std::min(cap, s1 + (target - r1) / slope) : s1;
}

/// The next noise to try: 0 after the first run, then the residual interpolated linearly between
/// the runs that bracket the target (the residual grows with the noise and saturates, as the
/// matcher trims what is far off), or extrapolated past the largest (at most 3x).
double nextRangeNoise(const std::vector<std::pair<double, double>>& runs, double target) {
  if (runs.size() == 1) return 0.0;
  return secantStep(runs, target, 3.0 * std::max_element(runs.begin(), runs.end())->first);
}

/// Beyond, the noise is an offset that drifts across the scan more than noise (33 beams' length).
constexpr double kMaxNoiseCorrelation = 0.97;

/// The next correlation to try: none while the uncorrelated run measures the target already, else
/// the target itself first (an AR(1)'s neighbour correlation), then interpolated or
/// extrapolated like the noise. `runs`: (correlation, measured) of the runs with noise.
double nextNoiseCorrelation(const std::vector<std::pair<double, double>>& runs, double target) {
  if (runs.size() == 1)
    return runs[0].second >= target ? runs[0].first : std::min(kMaxNoiseCorrelation, target);
  return std::clamp(secantStep(runs, target, kMaxNoiseCorrelation), 0.0, kMaxNoiseCorrelation);
}

/// The next share of the noise fixed in the world: the first run's plus what its revisit
/// correlation missed, then interpolated or extrapolated like the noise. `runs`: (share,
/// measured revisit correlation) of the runs with noise.
double nextFixedShare(const std::vector<std::pair<double, double>>& runs, double target) {
  const double next = runs.size() == 1 ? runs[0].first + (target - runs[0].second)
                                       : secantStep(runs, target, kMaxFixedShare);
  return std::clamp(next, 0.0, kMaxFixedShare);
}

}  // namespace

namespace {

/// A run without slip measured as the recording was (recordingSlipInput): against its scans
/// matched alone, its wheels turned by the agreement's ratios, moved by the clock offset it was
/// given. What its physics slips, and what its matcher and its lidar's sweep add as in the
/// recording (against the ground truth they were left out of one side). The run at the tuned
/// range noise: the first one's, fitted against the world, can be far off (fsm_bag 0.129 m for
/// 0), and its matches showed fsm_bag's twin a slip of 0.116 and a jitter of 0.26 s.
WheelSlipFit slipWithoutSlip(const TwinFit& fit, const Dataset& d) {
  const PoseSeries scan_only = matchScansAlone(d, fit.deskew, false);
  const algo::SensorAgreement agreement = scanAgreement(d, scan_only);
  const algo::PairAgreement* p = algo::wheelsAgainstScans(agreement);
  const sim::FaultsConfig& faults = fit.config.faults;
  const double lag_s = faults.enable.has(sim::Fault::clock_offset) ? faults.clock_offset_s : 0.0;
  return fitWheelSlip(slipAgainstScans(
      d, "the twin", scan_only,
      turningGeometry(*d.info.true_geometry, p ? p->wheel_ratios : std::nullopt), lag_s));
}

/// The recording's slip fitted again with its reference noise held at what the twin's own scans
/// show on the same drive (`physics`), where that is less, and its slips as they were: the rest
/// of that noise, which does not grow with the piece as a slip does, is not its matcher's, and
/// the timing takes it. nullopt where it is not less.
std::optional<WheelSlipFit> slipBeyondTheMatcher(const TwinFit& fit, const WheelSlipFit& physics) {
  const WheelSlipFit& free = fit.recording_slip;
  if (!free.fitted || !physics.fitted || !(physics.reference_noise_rad < free.reference_noise_rad))
    return std::nullopt;
  WheelSlipParams params;
  params.reference_noise_rad = physics.reference_noise_rad;
  params.slip_sigma = free.sigma;
  params.turn_slip_sigma = free.turn_sigma;
  WheelSlipFit held = fitWheelSlip(fit.recording_slip_input, params);
  if (!held.fitted) return std::nullopt;
  return held;  // Eq. (2) as first fitted: it reads the heading fit's wheel slip, held
}

/// The twin's random slips: the recording's less what a run without them shows already,
/// measured the same way (variances add). True when the twin is given some.
bool setSlip(TwinFit& fit, const sim::SimResult& without) {
  const WheelSlipFit physics = slipWithoutSlip(fit, without.dataset);
  const std::optional<WheelSlipFit> held = slipBeyondTheMatcher(fit, physics);
  const WheelSlipFit& recording = held ? *held : fit.recording_slip;
  const auto beyond = [](double real, double physics_sigma) {
    return std::sqrt(std::max(0.0, real * real - physics_sigma * physics_sigma));
  };
  nlohmann::ordered_json& j = fit.json["odometry"]["slip"];
  // Beyond the simulator's range the heading errors are not slip (failed matches, a held
  // robot): the twin slips as much as the simulator can, and says so.
  const auto given = [&j](const char* key, double value) {
    if (value > sim::kMaxSlipSigma)
      j["capped"].push_back(std::string(key) + ": " + num(value) + " is beyond the simulator's " +
                            num(sim::kMaxSlipSigma) + ", the twin is given " +
                            num(sim::kMaxSlipSigma));
    return std::min(value, sim::kMaxSlipSigma);
  };
  const double sigma = given("twin_sigma", beyond(recording.sigma, physics.sigma));
  const double turn_sigma =
      given("twin_turn_sigma", beyond(recording.turn_sigma, physics.turn_sigma));
  const double jitter_s = beyond(recording.timing_jitter_s, physics.timing_jitter_s);
  const double common_sigma =
      given("twin_common_sigma", beyond(recording.common_sigma, physics.common_sigma));
  const auto measured = [&](double v) {
    return physics.fitted ? nlohmann::ordered_json(v) : nlohmann::ordered_json(nullptr);
  };
  j["physics_reference_noise_rad"] = measured(physics.reference_noise_rad);
  j["reference_noise_held"] =
      !held
          ? nlohmann::ordered_json(nullptr)
          : nlohmann::ordered_json{{"reference_noise_rad", recording.reference_noise_rad},
                                   {"sigma", recording.sigma},
                                   {"turn_sigma", recording.turn_sigma},
                                   {"timing_jitter_s", recording.timing_jitter_s},
                                   {"timing_likelihood_ratio", recording.timing_likelihood_ratio}};
  j["physics_sigma"] = measured(physics.sigma);
  j["twin_sigma"] = sigma;
  j["physics_turn_sigma"] = measured(physics.turn_sigma);
  j["twin_turn_sigma"] = turn_sigma;
  j["physics_timing_jitter_s"] = measured(physics.timing_jitter_s);
  j["twin_read_jitter_s"] = jitter_s;
  j["physics_common_sigma"] =
      physics.common_fitted ? nlohmann::ordered_json(physics.common_sigma) : nullptr;
  j["twin_common_sigma"] = common_sigma;
  if (sigma > 0.0) setKey(fit, "encoders.slip_sigma", num(sigma));
  if (turn_sigma > 0.0) setKey(fit, "encoders.turn_slip_sigma", num(turn_sigma));
  if (common_sigma > 0.0) setKey(fit, "encoders.common_slip_sigma", num(common_sigma));
  if (jitter_s > 0.0) {
    setKey(fit, "faults.read_jitter.encoders_sigma_s", num(jitter_s));
    sim::FaultSet faults = fit.config.faults.enable;
    faults.add(sim::Fault::read_jitter);
    setKey(fit, "faults.enable", sim::toString(faults));
  }
  return sigma > 0.0 || turn_sigma > 0.0 || jitter_s > 0.0 || common_sigma > 0.0;
}

}  // namespace

namespace {

void setNoiseCorrelation(TwinFit& fit, double rho) {
  if (rho == fit.config.lidar.range_noise_correlation) return;
  setKey(fit, "lidar.range_noise_correlation", num(rho));
  fit.json["lidar"]["range_noise_correlation"]["value"] = rho;
}

/// A setting tuned to a statistic of the recording: its value, the recording's figure, the runs.
void tuned(nlohmann::ordered_json& j, double value, const char* recording_key,
           double recording_value, const std::vector<std::pair<double, double>>& runs,
           const std::string& how) {
  j["value"] = value;
  j[recording_key] = recording_value;
  j["tuning_runs"] = runs;
  j["how"] = how;
}

void describeTuning(TwinFit& fit, const std::vector<std::pair<double, double>>& noise_runs,
                    const std::vector<std::pair<double, double>>& correlation_runs,
                    const std::vector<std::pair<double, double>>& share_runs) {
  tuned(fit.json["lidar"]["range_noise_fixed_share"], fit.range_noise_fixed_share,
        "recording_revisit_correlation", fit.residual_revisit_correlation, share_runs,
        "the share of range_noise_m's variance fixed in the world (lidar.range_noise_fixed_m, a "
        "Gaussian texture of 2 cm correlation length over the surfaces, the same wherever a spot "
        "is seen again), the rest drawn afresh each scan; tuned alongside the noise so that the "
        "twin's scans see their residual again as the recording's do (the revisit correlation "
        "against each dataset's own map, twin --compare's scan_residual_revisit_correlation): "
        "first the recording's revisit correlation, then moved by what the run missed, then "
        "interpolated (at most " +
            num(kMaxFixedShare) +
            "); tuning_runs: [share, the twin's revisit correlation] of the runs with noise "
            "before the last");
  nlohmann::ordered_json& noise = fit.json["lidar"]["range_noise_m"];
  noise["tuning_runs"] = noise_runs;
  noise["how"] =
      "tuned so the twin's scan-to-map residual (match --deskew none, median) is the "
      "recording's: a run at the range residual against the world "
      "(fitted_against_the_world_m), one at zero noise, then the noise interpolated between the "
      "runs that bracket the recording's residual (4 runs at most, without slip; the last is "
      "the twin, or, where it is given slip (odometry.slip), one more run with it); "
      "tuning_runs: [noise, the twin's residual] of the runs before the last";
  tuned(fit.json["lidar"]["range_noise_correlation"], fit.config.lidar.range_noise_correlation,
        "recording_neighbour_correlation", fit.residual_neighbour_correlation, correlation_runs,
        "the AR(1) correlation of the range noise along the scan, tuned so that neighbouring "
        "beams' residuals against each dataset's own map (the scans matched de-skewed, robust "
        "correlation) correlate as the recording's: none while the uncorrelated first run's do "
        "already, then the recording's correlation, then interpolated between the runs that "
        "bracket it or extrapolated (at most 0.97), alongside the noise; tuning_runs: "
        "[correlation, the twin's neighbour correlation] of the runs with noise before the last");
}

}  // namespace

sim::SimResult simulateTwin(TwinFit& fit, const sim::Scenario& scenario) {
  const double target = fit.residual_median_m;
  std::vector<std::pair<double, double>> noise_runs;        // (noise, the twin's residual)
  std::vector<std::pair<double, double>> correlation_runs;  // (correlation, the twin's)
  std::vector<std::pair<double, double>> share_runs;        // (fixed share, twin's revisit)
  sim::SimResult r;
  nlohmann::ordered_json& j = fit.json["lidar"]["range_noise_m"];
  j["fitted_against_the_world_m"] = totalRangeNoise(fit.config.lidar);
  j["recording_residual_m"] = target;
  constexpr int kTuningRuns = 4;
  // The runs differ in the lidar's noise and then the encoders' slip: one physics for all.
  sim::RecordedMotion motion;
  for (int k = 0; k < kTuningRuns; ++k) {
    r = k == 0 ? firstRun(fit, scenario, motion)
               : sim::simulate(fit.config, fit.world, scenario, motion);
    if (k == kTuningRuns - 1 || target <= 0.0) break;
    const MatchedScans m = measureMatchedScans(r.dataset, fit.layout, fit.walls, fit.lidar);
    const sim::LidarConfig& lidar = fit.config.lidar;
    noise_runs.push_back({totalRangeNoise(lidar), m.residual_median_m});
    if (lidar.range_noise_m > 0.0)
      correlation_runs.push_back({lidar.range_noise_correlation, m.neighbour_correlation});
    if (lidar.range_noise_fixed_m > 0.0)
      share_runs.push_back({fit.range_noise_fixed_share, m.revisit_correlation});
    const double next = std::max(0.0, nextRangeNoise(noise_runs, target));
    const double next_rho =
        correlation_runs.empty()
            ? lidar.range_noise_correlation
            : nextNoiseCorrelation(correlation_runs, fit.residual_neighbour_correlation);
    const double next_share = share_runs.empty()
                                  ? fit.range_noise_fixed_share
                                  : nextFixedShare(share_runs, fit.residual_revisit_correlation);
    if (k > 0 && std::abs(next - totalRangeNoise(lidar)) < 1e-4 &&
        std::abs(next_rho - lidar.range_noise_correlation) < 1e-3 &&
        std::abs(next_share - fit.range_noise_fixed_share) < 1e-3)
      break;  // this run is the twin, but for its slip
    fit.range_noise_fixed_share = next_share;
    setRangeNoise(fit, next);
    setNoiseCorrelation(fit, next_rho);
  }
  // The slip is measured on the tuned run, whose matches are as noisy as the twin's will be.
  if (setSlip(fit, r)) r = sim::simulate(fit.config, fit.world, scenario, motion);
  // No noise has no correlation: said so (the run is the same, as 0 times any draw is 0).
  if (fit.config.lidar.range_noise_m == 0.0) setNoiseCorrelation(fit, 0.0);
  describeTuning(fit, noise_runs, correlation_runs, share_runs);
  return r;
}

}  // namespace slamprep::eval
