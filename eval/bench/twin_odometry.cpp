#include "slamprep/eval/bench/twin_odometry.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>

#include "slamprep/algo/timing/dataset_stamps.hpp"
#include "slamprep/algo/timing/stamp_checks.hpp"
#include "slamprep/algo/timing/stamp_grid.hpp"
#include "slamprep/core/order_statistics.hpp"
#include "slamprep/core/se2.hpp"

namespace slamprep::eval {
namespace {

/// Mean and standard deviation of the gyro where the wheels did not turn between two
/// encoder samples.
void fitGyro(const Dataset& d, const OdometryFitParams& p, OdometryFit& f) {
  std::vector<double> imu_stamps;
  for (const ImuSample& s : d.imu) imu_stamps.push_back(s.stamp_s);
  const double imu_step = medianSpacing(imu_stamps);
  f.imu_rate_hz = imu_step > 0.0 ? 1.0 / imu_step : 0.0;
  std::vector<double> still;
  std::size_t e = 0;
  for (const ImuSample& s : d.imu) {
    while (e + 1 < d.encoders.size() && d.encoders[e + 1].stamp_s < s.stamp_s) ++e;
    if (e + 1 >= d.encoders.size() || d.encoders[e].stamp_s > s.stamp_s) continue;
    const EncoderSample& a = d.encoders[e];
    const EncoderSample& b = d.encoders[e + 1];
    if (a.ticks_left == b.ticks_left && a.ticks_right == b.ticks_right)
      still.push_back(s.gyro_z_radps);
  }
  f.still_samples = still.size();
  if (still.size() < p.min_still) return;
  double sum = 0.0, sq = 0.0;
  for (double g : still) sum += g;
  f.gyro_bias_radps = sum / double(still.size());
  for (double g : still) sq += (g - f.gyro_bias_radps) * (g - f.gyro_bias_radps);
  f.gyro_noise_radps = std::sqrt(sq / double(still.size() - 1));
}

/// |wheel rate| of every step of the encoders, else of the odometry poses (nominal geometry).
std::vector<double> wheelRates(const Dataset& d) {
  std::vector<double> rates;
  const double rad_per_tick = 2.0 * std::numbers::pi / std::max(1, d.info.ticks_per_revolution);
  for (std::size_t k = 1; k < d.encoders.size(); ++k) {
    const double dt = d.encoders[k].stamp_s - d.encoders[k - 1].stamp_s;
    if (dt <= 0.0) continue;
    for (double ticks : {double(d.encoders[k].ticks_left - d.encoders[k - 1].ticks_left),
                         double(d.encoders[k].ticks_right - d.encoders[k - 1].ticks_right)})
      rates.push_back(std::abs(ticks) * rad_per_tick / dt);
  }
  if (!rates.empty()) return rates;
  const auto& odom = d.odom_nominal.samples();
  for (std::size_t k = 1; k < odom.size(); ++k) {
    const double dt = odom[k].stamp_s - odom[k - 1].stamp_s;
    if (dt <= 0.0) continue;
    const SE2 step = between(odom[k - 1].value, odom[k].value);
    const Eigen::Vector2d w = d.info.nominal_geometry.wheelRates(step.x / dt, step.yaw / dt);
    rates.push_back(std::abs(w.x()));
    rates.push_back(std::abs(w.y()));
  }
  return rates;
}

/// What calibrate's stamp regularisation finds on each stream (on a copy): its jitter where it
/// puts the stream back on its grid, which the twin then adds to its own stamps; the encoders'
/// no more than their ticks say their stamps can be wrong (algo::tickStampErrorBound), the rest
/// being when they were sampled.
void fitStampJitter(const Dataset& d, OdometryFit& f) {
  Dataset copy = d;
  for (const algo::StreamStamps& s : algo::regularizeStamps(copy)) {
    if (!s.applied && !s.stamped_right) continue;
    if (s.stream == "encoders" || (s.stream == "odometry" && d.encoders.size() < 2)) {
      f.encoders_grid_jitter_s = s.residual_rms_s;
      f.encoders_stamp_error_bound_s = algo::tickStampErrorBound(d.encoders);
      f.encoders_jitter_s =
          std::min(s.residual_rms_s, f.encoders_stamp_error_bound_s.value_or(s.residual_rms_s));
      // The rest of the jitter about the grid is when the samples were taken (variances add).
      f.encoders_sampling_jitter_s = std::sqrt(std::max(
          0.0, s.residual_rms_s * s.residual_rms_s - f.encoders_jitter_s * f.encoders_jitter_s));
    } else if (s.stream == "imu")
      f.imu_jitter_s = s.residual_rms_s;
    else if (s.stream == "scans")
      f.scans_jitter_s = s.residual_rms_s;
  }
}

}  // namespace

OdometryFit fitOdometry(const Dataset& d, const OdometryFitParams& p) {
  OdometryFit f;
  f.ticks_per_revolution = d.info.ticks_per_revolution;
  // A log without encoder ticks (CARMEN without --nominal): its odometry poses' stream.
  std::vector<double> stamps;
  for (const EncoderSample& e : d.encoders) stamps.push_back(e.stamp_s);
  if (stamps.size() < 2) {
    stamps.clear();
    for (const auto& s : d.odom_nominal.samples()) stamps.push_back(s.stamp_s);
  }
  if (stamps.size() >= 2) {
    f.duration_s = stamps.back() - stamps.front();
    std::vector<double> steps;
    for (std::size_t k = 1; k < stamps.size(); ++k) steps.push_back(stamps[k] - stamps[k - 1]);
    const double step = median(steps);
    const double period = algo::streamPeriod(stamps);
    f.encoder_rate_hz = period > 0.0 ? 1.0 / period : 0.0;
    double missing = 0.0;
    for (double dt : steps) {
      if (dt <= p.gap_periods * step) continue;
      ++f.gaps;
      missing += dt - step;
      f.gap_max_s = std::max(f.gap_max_s, dt - step);
    }
    if (f.gaps > 0) f.gap_mean_s = missing / double(f.gaps);
  }
  f.wheel_rate_p99_radps = quantile(wheelRates(d), 0.99);
  f.has_imu = !d.imu.empty();
  if (f.has_imu) fitGyro(d, p, f);
  fitStampJitter(d, f);
  return f;
}

DatasetCalibration calibrateForTwin(const std::string& dir, const Dataset& dataset) {
  DatasetCalibrationParams c;
  c.dataset = dir;
  c.methods = {algo::CalibrationMethod::kJoint};
  c.motion.source = MotionSource::kMap;
  c.motion.intervals.keyframe_translation_m = 0.2;
  // The twin compares sigma(b) itself, also where it is too large for calibrate to accept the
  // estimate (undetermined): the statistic must not vanish where it is largest.
  c.params.max_relative_sigma = 0.0;
  // The data alone on both sides: a twin's dataset has no measured mount to take as a prior.
  c.mount_prior = false;
  return calibrateDataset(c, dataset);
}

}  // namespace slamprep::eval
