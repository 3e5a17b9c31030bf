#pragma once
// A small dataset made in code (no Bullet): the robot drives a constant-twist arc inside a
// circular wall, with exact ground truth, encoders of the true wheels, nominal odometry, a planar
// IMU and a rotating lidar whose beams are taken one after another.

#include <cmath>
#include <limits>
#include <numbers>

#include "slamprep/core/dataset.hpp"
#include "slamprep/core/odometry.hpp"

namespace slamprep::test {

struct SyntheticParams {
  double duration_s = 2.0;
  double v_mps = 0.5;
  double w_radps = 0.3;
  double wall_radius_m = 10.0;
  int beams = 360;
  double lidar_rate_hz = 10.0;
  bool clockwise = false;
  double start_s = 0.0;  ///< stamp of the first sample
};

inline Dataset makeSyntheticDataset(const SyntheticParams& p = {}) {
  Dataset d;
  d.info.world = "synthetic";
  d.info.scenario = "arc";
  d.info.seed = 7;
  d.info.true_geometry = DiffDriveParams{0.101, 0.099, 0.52};
  d.info.nominal_geometry = DiffDriveParams{0.1, 0.1, 0.5};
  d.info.T_base_lidar = SE2(0.1, 0.02, 0.05);
  d.info.ticks_per_revolution = 4096;
  const SE2 T_world_start(1.0, 2.0, 0.3);
  auto truth = [&](double t) {
    return T_world_start * SE2::exp(Eigen::Vector3d(p.v_mps * t, 0.0, p.w_radps * t));
  };
  const double t0 = p.start_s;
  for (int k = 0; k <= int(p.duration_s * 200); ++k)  // 200 Hz ground truth
    d.groundtruth.push_back(t0 + k * 0.005, truth(k * 0.005));
  // Encoders of the true wheels at 100 Hz.
  const DiffDriveParams& g = *d.info.true_geometry;
  const Eigen::Vector2d rates = g.wheelRates(p.v_mps, p.w_radps);
  const double rad_per_tick = radiansPerTick(d.info.ticks_per_revolution);
  for (int k = 0; k <= int(p.duration_s * 100); ++k) {
    const double t = k * 0.01;
    d.encoders.push_back({t0 + t, std::llround(rates.x() * t / rad_per_tick),
                          std::llround(rates.y() * t / rad_per_tick)});
  }
  d.odom_nominal =
      integrateEncoders(d.encoders, d.info.nominal_geometry, d.info.ticks_per_revolution);
  for (int k = 0; k <= int(p.duration_s * 200); ++k)
    d.imu.push_back({t0 + k * 0.005, p.w_radps, 0.0, p.v_mps * p.w_radps});
  // Scans: ranges to the wall from the lidar pose at each beam's own time.
  const double period = 1.0 / p.lidar_rate_hz;
  for (int s = 0; (s + 1) * period <= p.duration_s; ++s) {
    ScanRecord r;
    LaserScan& scan = r.scan;
    scan.stamp_s = t0 + s * period;
    scan.angle_increment_rad = (p.clockwise ? -1 : 1) * 2 * std::numbers::pi / p.beams;
    scan.angle_min_rad = p.clockwise ? std::numbers::pi : -std::numbers::pi;
    scan.time_increment_s = period / p.beams;
    scan.scan_time_s = period;
    scan.range_min_m = 0.05;
    scan.range_max_m = 30.0;
    for (int i = 0; i < p.beams; ++i) {
      const double t = s * period + i * scan.time_increment_s;
      const SE2 T_world_lidar = truth(t) * d.info.T_base_lidar;
      const double a = T_world_lidar.yaw + scan.beamAngle(i);
      const Eigen::Vector2d o = T_world_lidar.translation(), u(std::cos(a), std::sin(a));
      // |o + r u| = R  ->  r = -o.u + sqrt((o.u)^2 - |o|^2 + R^2)
      const double b = o.dot(u);
      const double range =
          -b + std::sqrt(b * b - o.squaredNorm() + p.wall_radius_m * p.wall_radius_m);
      scan.ranges_m.push_back(i % 37 == 5 ? std::numeric_limits<double>::infinity() : range);
    }
    r.T_world_base_true = truth(s * period);
    r.T_odom_base_nominal = d.odom_nominal.at(scan.stamp_s);
    d.scans.push_back(std::move(r));
  }
  return d;
}

}  // namespace slamprep::test
