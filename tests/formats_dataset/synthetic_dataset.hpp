#pragma once
// A deterministic synthetic Dataset for I/O tests and the I/O benchmark: full-precision random
// doubles (so text round trips are really exercised), no-return beams, and awkward values
// (-0.0, yaw = pi, integers stored as doubles).

#include <cmath>
#include <limits>
#include <numbers>
#include <random>

#include "slamprep/core/dataset.hpp"

namespace slamprep::synthetic {

struct SyntheticDatasetParams {
  double duration_s = 2.0;       ///< length of the run
  double groundtruth_hz = 1000;  ///< ground-truth pose rate
  double encoder_hz = 100;       ///< encoder rate
  double imu_hz = 200;           ///< IMU rate
  double scan_hz = 10;           ///< lidar revolutions per second
  int beams = 720;               ///< beams per scan
  bool with_truth = true;        ///< simulated (true) or real-log-like (false)
  /// Real-log-like extras: the log's own odometry beside the encoders (odometry_logged.tum),
  /// and a beam count that changes scan to scan (a cheap lidar's), up to `beams`.
  bool logged_odometry = false;
  bool varying_beams = false;
  std::uint64_t seed = 7;  ///< RNG seed
};

inline Dataset makeSyntheticDataset(const SyntheticDatasetParams& p) {
  std::mt19937_64 rng(p.seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  auto noisy = [&](double scale) { return scale * (2.0 * unit(rng) - 1.0); };
  // A wobbly circle: full-precision doubles everywhere.
  auto pose = [](double t) {
    return SE2(3.0 * std::sin(0.1 * t) + 0.01 * std::sin(7.0 * t), 2.0 - 2.0 * std::cos(0.1 * t),
               0.1 * t + 0.3 * std::sin(0.5 * t));
  };

  Dataset d;
  d.info.world = "worlds/office.yaml";
  d.info.scenario = "worlds/scenarios/loop.yaml";
  d.info.seed = 0xfedcba9876543210ULL;  // needs all 64 bits
  d.info.nominal_geometry = {0.1, 0.1, 0.5};
  if (p.with_truth) d.info.true_geometry = DiffDriveParams{0.1003 + noisy(1e-4), 0.0997, 0.5071};
  d.info.T_base_lidar = SE2(0.12 + noisy(0.01), -0.0, 0.05 + noisy(0.01));
  d.info.ticks_per_revolution = 4096;
  d.info.config = {
      {"lidar", {{"beams", p.beams}, {"noise_m", 0.01}}}, {"dt_s", 0.001}, {"names", {"a", "b"}}};

  const double t0 = 1700000000.0 + noisy(1.0);  // epoch-like stamps: 10+ significant digits
  const int n_gt = p.with_truth ? static_cast<int>(p.duration_s * p.groundtruth_hz) : 0;
  for (int k = 0; k < n_gt; ++k) {
    const double t = k / p.groundtruth_hz;
    d.groundtruth.push_back(t0 + t, pose(t));
  }
  if (n_gt > 2) d.groundtruth.push_back(t0 + p.duration_s + 1.0, SE2(-0.0, 1.0, std::numbers::pi));

  // Encoders (and the odometry) from one sample before the first scan to past the last beam of
  // the last scan: readDataset refuses scans the odometry does not cover.
  const int n_enc = static_cast<int>(p.duration_s * p.encoder_hz) + 3;
  std::int64_t left = 0, right = 0;
  for (int k = 0; k < n_enc; ++k) {
    const double t = t0 + (k - 1) / p.encoder_hz + noisy(1e-5);
    left += 30 + static_cast<std::int64_t>(unit(rng) * 5) - (k % 50 == 0 ? 100 : 0);
    right += 31 + static_cast<std::int64_t>(unit(rng) * 5);
    d.encoders.push_back({t, left, right});
    d.odom_nominal.push_back(t, pose(t - t0) * SE2(noisy(0.05), noisy(0.05), noisy(0.05)));
    if (p.logged_odometry)
      d.odometry_logged.push_back(t + 1e-4, pose(t - t0) * SE2(noisy(0.05), 0.0, noisy(0.05)));
  }
  const int n_imu = static_cast<int>(p.duration_s * p.imu_hz);
  for (int k = 0; k < n_imu; ++k)
    d.imu.push_back({t0 + k / p.imu_hz, noisy(1.0), noisy(2.0), k == 0 ? -0.0 : noisy(2.0)});

  const int n_scans = static_cast<int>(p.duration_s * p.scan_hz);
  const double inf = std::numeric_limits<double>::infinity();
  for (int s = 0; s < n_scans; ++s) {
    ScanRecord r;
    LaserScan& scan = r.scan;
    const int beams = p.varying_beams ? p.beams - (s * 37) % (p.beams / 2) : p.beams;
    scan.stamp_s = t0 + s / p.scan_hz + noisy(1e-4);
    scan.angle_min_rad = -std::numbers::pi;
    scan.angle_increment_rad = 2.0 * std::numbers::pi / beams;
    scan.scan_time_s = 1.0 / p.scan_hz;
    scan.time_increment_s = scan.scan_time_s / beams;
    scan.range_min_m = 0.1;
    scan.range_max_m = s % 2 ? 30.0 : inf;
    scan.ranges_m.resize(beams);
    for (int i = 0; i < beams; ++i) {
      const double u = unit(rng);
      scan.ranges_m[i] = u < 0.1 ? inf : u < 0.12 ? 0.05 : 0.1 + 29.0 * unit(rng);
      if (i == 1 && s == 0) scan.ranges_m[i] = 2.0;  // an integer-valued range
    }
    r.T_odom_base_nominal = pose(scan.stamp_s - t0) * SE2(noisy(0.05), noisy(0.05), noisy(0.05));
    if (p.with_truth) {
      r.T_world_base_true = pose(scan.stamp_s - t0);
      r.p_ref_true.resize(beams);
      for (int i = 0; i < beams; ++i)
        if (std::isfinite(scan.ranges_m[i]))
          r.p_ref_true[i] = scan.point(i) + Eigen::Vector2d(noisy(0.01), noisy(0.01));
    }
    d.scans.push_back(std::move(r));
  }
  return d;
}

}  // namespace slamprep::synthetic
