#include "slamprep/sim/physics/lidar.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

#include "slamprep/core/number_list.hpp"

namespace slamprep::sim {

std::optional<std::vector<double>> parseRangeBias(std::string_view text, std::string* error) {
  constexpr NumberListRule kBias{-1.0, 1.0, 100000, "a number in [-1, 1]"};
  return parseNumberList(text, kBias, error);
}

double rangeBiasAt(const std::vector<double>& bias_by_metre_m, double range_m) {
  if (bias_by_metre_m.empty()) return 0.0;
  const double last = static_cast<double>(bias_by_metre_m.size() - 1);
  const double at = std::clamp(range_m, 0.0, last);
  const auto below = static_cast<std::size_t>(std::floor(at));
  if (below + 1 >= bias_by_metre_m.size()) return bias_by_metre_m.back();
  const double t = at - static_cast<double>(below);
  return (1.0 - t) * bias_by_metre_m[below] + t * bias_by_metre_m[below + 1];
}

Lidar::Lidar(const LidarConfig& config, std::uint64_t seed)
    : config_(config),
      rng_(seed),
      bias_by_beam_m_(
          parseRangeBias(config.range_bias_by_beam_m, nullptr).value_or(std::vector<double>{})),
      bias_by_range_m_(
          parseRangeBias(config.range_bias_by_range_m, nullptr).value_or(std::vector<double>{})) {
  // Its own stream: a lidar without the texture draws its noise as before.
  if (config.range_noise_fixed_m > 0.0)
    texture_.emplace(config.range_noise_fixed_length_m, seed ^ 0x74657874ULL /* "text" */);
  assert(config.rate_hz > 0 && config.beams_per_revolution > 0);
  assert(config.fov_rad > 0 && config.fov_rad <= 2 * std::numbers::pi + 1e-12);
  assert(config.range_min_m >= 0 && config.range_max_m > config.range_min_m);
  beams_per_scan_ = static_cast<std::size_t>(
      std::lround(config.beams_per_revolution * config.fov_rad / (2 * std::numbers::pi)));
  // Beams are evenly spaced over the revolution; the scan is centred on the lidar's x axis and
  // starts at -fov/2 (counter-clockwise) or +fov/2 (clockwise).
  const double step = 2 * std::numbers::pi / config.beams_per_revolution;
  angle_increment_rad_ = config.clockwise ? -step : step;
  angle_min_rad_ = config.clockwise ? config.fov_rad / 2 : -config.fov_rad / 2;
}

LaserScan Lidar::header(double stamp_s) const {
  LaserScan scan;
  scan.stamp_s = stamp_s;
  scan.angle_min_rad = angle_min_rad_;
  scan.angle_increment_rad = angle_increment_rad_;
  const double sweep_s = config_.sweep_s > 0.0 ? config_.sweep_s : 1.0 / config_.rate_hz;
  scan.time_increment_s = sweep_s / config_.beams_per_revolution;
  scan.scan_time_s = 1.0 / config_.rate_hz;
  scan.range_min_m = config_.range_min_m;
  scan.range_max_m = config_.range_max_m;
  scan.ranges_m.assign(beams_per_scan_, std::numeric_limits<double>::infinity());
  return scan;
}

double Lidar::revolutionOffset(double stamp_s) const {
  const double sweep_s = config_.sweep_s;
  // A head as fast as the publishing (sweep_s 0 or 1 / rate) starts every scan at its stamp.
  if (!config_.free_running || !(sweep_s > 0.0) || sweep_s * config_.rate_hz > 1.0 - 1e-9)
    return 0.0;
  return sweep_s * std::round(stamp_s / sweep_s) - stamp_s;
}

Lidar::Beam Lidar::measure(const Scene& scene, const SE2& T_world_lidar, std::size_t i) {
  const double yaw = T_world_lidar.yaw + beamAngle(i);
  return measure(scene, T_world_lidar.translation(), Eigen::Vector2d(std::cos(yaw), std::sin(yaw)),
                 i);
}

Lidar::Beam Lidar::measure(const Scene& scene, const Eigen::Vector2d& origin_world_m,
                           const Eigen::Vector2d& dir_world, std::size_t i,
                           std::optional<double> moving_m) {
  assert(i < beams_per_scan_);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  // One draw per beam, hit or not, so beam i's noise depends only on the seed and i (correlated:
  // and on the scan's beams before it, an AR(1) along the scan that restarts at beam 0).
  double noise_m = config_.range_noise_m * gaussian();
  if (const double rho = config_.range_noise_correlation; rho > 0.0 && i > 0)
    noise_m = rho * last_noise_m_ + std::sqrt(1.0 - rho * rho) * noise_m;
  last_noise_m_ = noise_m;
  std::optional<double> hit =
      scene.castRay(origin_world_m, dir_world, config_.height_m, config_.range_max_m);
  if (moving_m && (!hit || *moving_m < *hit)) hit = moving_m;
  if (!hit) return {kInf, kInf};
  if (texture_)
    noise_m += config_.range_noise_fixed_m * texture_->at(origin_world_m + *hit * dir_world);
  if (i < bias_by_beam_m_.size()) noise_m += bias_by_beam_m_[i];
  noise_m += rangeBiasAt(bias_by_range_m_, *hit);
  const double measured_m = *hit + noise_m;
  const bool in_limits = measured_m >= config_.range_min_m && measured_m <= config_.range_max_m;
  return {in_limits ? measured_m : kInf, *hit};
}

/// Standard normal by the Box-Muller transform on the 53-bit uniforms of mt19937_64, so the
/// numbers are the same on every standard library (std::normal_distribution is not).
double Lidar::gaussian() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_gaussian_;
  }
  constexpr double kTwoPow53 = 9007199254740992.0;
  const double u1 = (static_cast<double>(rng_() >> 11) + 1.0) / (kTwoPow53 + 1.0);  // (0, 1]
  const double u2 = static_cast<double>(rng_() >> 11) / kTwoPow53;                  // [0, 1)
  const double radius = std::sqrt(-2.0 * std::log(u1));
  const double angle = 2 * std::numbers::pi * u2;
  spare_gaussian_ = radius * std::sin(angle);
  has_spare_ = true;
  return radius * std::cos(angle);
}

}  // namespace slamprep::sim
