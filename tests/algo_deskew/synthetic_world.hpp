#pragma once
// Test-only synthetic data: an analytic 2D world of line segments, robot trajectories sampled
// like a physics engine (poses at a fixed step, geodesic in between, as docs/design.md defines
// truth), and a rotating lidar ray-cast beam by beam while the robot moves. No Bullet, exact
// geometry.

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include "slamprep/core/laser_scan.hpp"
#include "slamprep/core/se2.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep::testing {

struct Segment {
  Eigen::Vector2d a, b;
};

/// A 10 m x 8 m room centred on the origin with a few boxes and a slanted wall, so that scans
/// constrain x, y and yaw everywhere.
inline std::vector<Segment> roomWorld() {
  std::vector<Segment> w;
  auto box = [&w](double x0, double y0, double x1, double y1) {
    w.push_back({{x0, y0}, {x1, y0}});
    w.push_back({{x1, y0}, {x1, y1}});
    w.push_back({{x1, y1}, {x0, y1}});
    w.push_back({{x0, y1}, {x0, y0}});
  };
  box(-5.0, -4.0, 5.0, 4.0);
  box(1.5, 1.0, 2.3, 1.6);
  box(-3.0, -2.5, -2.2, -1.2);
  box(2.5, -3.0, 3.1, -2.2);
  w.push_back({{-4.0, 2.0}, {-2.0, 3.5}});
  w.push_back({{0.5, -3.2}, {-0.8, -2.6}});
  return w;
}

/// Range along a ray from `origin` in direction `angle_rad`; +inf when nothing is hit.
inline double castRay(const std::vector<Segment>& world, const Eigen::Vector2d& origin,
                      double angle_rad, double range_max_m) {
  const Eigen::Vector2d d(std::cos(angle_rad), std::sin(angle_rad));
  double best = std::numeric_limits<double>::infinity();
  for (const Segment& s : world) {
    const Eigen::Vector2d e = s.b - s.a;
    const double denom = d.x() * e.y() - d.y() * e.x();
    if (std::abs(denom) < 1e-15) continue;
    const Eigen::Vector2d w = s.a - origin;
    const double t = (w.x() * e.y() - w.y() * e.x()) / denom;  // along the ray
    const double u = (w.x() * d.y() - w.y() * d.x()) / denom;  // along the segment
    if (t > 1e-9 && u >= 0.0 && u <= 1.0) best = std::min(best, t);
  }
  return best <= range_max_m ? best : std::numeric_limits<double>::infinity();
}

/// A scan from a standing lidar in `room`: `beams` over the full turn from -pi, exact ranges.
inline Points2 standingScan(const std::vector<Segment>& world, const SE2& T_world_lidar,
                            int beams) {
  Points2 points;
  for (int i = 0; i < beams; ++i) {
    const double a = -std::numbers::pi + i * 2.0 * std::numbers::pi / beams;
    const double r = castRay(world, T_world_lidar.translation(), T_world_lidar.yaw + a, 30.0);
    if (std::isfinite(r)) points.push_back(r * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return points;
}

/// Robot motion with constant linear and angular acceleration from T0 (body-frame twist rates).
struct Motion {
  SE2 T_world_base0;
  double v0_mps = 1.0;
  double w0_radps = 1.0;
  double a_mps2 = 0.0;
  double alpha_radps2 = 0.0;
};

/// Truth as a physics engine records it: poses every `step_s` from t0 to t1, integrated with fine
/// RK4 sub-steps (exact for constant twist), geodesic in between.
inline PoseSeries sampleTruth(const Motion& m, double t0_s, double t1_s, double step_s) {
  PoseSeries truth;
  Eigen::Vector3d x(m.T_world_base0.x, m.T_world_base0.y, m.T_world_base0.yaw);
  auto f = [&m](double tau, const Eigen::Vector3d& s) {
    const double v = m.v0_mps + m.a_mps2 * tau, w = m.w0_radps + m.alpha_radps2 * tau;
    return Eigen::Vector3d(v * std::cos(s.z()), v * std::sin(s.z()), w);
  };
  const int steps = static_cast<int>(std::llround((t1_s - t0_s) / step_s));
  const int sub = 20;
  for (int k = 0; k <= steps; ++k) {
    truth.push_back(t0_s + k * step_s, SE2(x.x(), x.y(), x.z()));
    for (int j = 0; j < sub; ++j) {  // RK4 in time since t0
      const double h = step_s / sub, tau = k * step_s + j * h;
      const Eigen::Vector3d k1 = f(tau, x), k2 = f(tau + h / 2, x + h / 2 * k1),
                            k3 = f(tau + h / 2, x + h / 2 * k2), k4 = f(tau + h, x + h * k3);
      x += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
    }
  }
  return truth;
}

/// A series re-sampled at `rate_hz` starting at t0 (noiseless odometry or oracle).
inline PoseSeries resample(const PoseSeries& truth, double t0_s, double t1_s, double rate_hz,
                           const SE2& T_odom_world = SE2()) {
  PoseSeries out;
  const int n = static_cast<int>(std::floor((t1_s - t0_s) * rate_hz + 1e-9));
  for (int k = 0; k <= n; ++k) {
    const double t = t0_s + k / rate_hz;
    if (const auto T = truth.at(t)) out.push_back(t, T_odom_world * *T);
  }
  return out;
}

struct SyntheticScan {
  LaserScan scan;
  /// Ground truth: each beam's measured point in the lidar frame at the first beam.
  std::vector<std::optional<Eigen::Vector2d>> p_ref_true;
};

struct LidarConfig {
  std::size_t beams = 720;
  double rate_hz = 10.0;  ///< one revolution per scan: time_increment = 1 / (rate * beams)
  double angle_min_rad = -std::numbers::pi;
  bool clockwise = false;
  double range_max_m = 30.0;
  double range_noise_m = 0.0;
};

/// One scan starting at `stamp_s`, each beam cast from the lidar pose at its own time.
inline SyntheticScan castScan(const std::vector<Segment>& world, const PoseSeries& truth,
                              const SE2& T_base_lidar, double stamp_s, const LidarConfig& cfg,
                              std::mt19937* rng = nullptr) {
  SyntheticScan out;
  LaserScan& s = out.scan;
  const double dir = cfg.clockwise ? -1.0 : 1.0;
  s.stamp_s = stamp_s;
  s.angle_min_rad = cfg.angle_min_rad;
  s.angle_increment_rad = dir * 2.0 * std::numbers::pi / cfg.beams;
  s.time_increment_s = 1.0 / (cfg.rate_hz * cfg.beams);
  s.scan_time_s = 1.0 / cfg.rate_hz;
  s.range_min_m = 0.05;
  s.range_max_m = cfg.range_max_m;
  const SE2 T_world_lidar0 = *truth.at(stamp_s) * T_base_lidar;
  std::normal_distribution<double> noise(0.0, cfg.range_noise_m);
  for (std::size_t i = 0; i < cfg.beams; ++i) {
    const SE2 T_world_lidar = *truth.at(s.beamTime(i)) * T_base_lidar;
    const double a = s.beamAngle(i);
    double r = castRay(world, T_world_lidar.translation(), T_world_lidar.yaw + a, cfg.range_max_m);
    if (std::isfinite(r) && rng && cfg.range_noise_m > 0.0) r += noise(*rng);
    s.ranges_m.push_back(r);
    if (!std::isfinite(r)) {
      out.p_ref_true.push_back(std::nullopt);
      continue;
    }
    const Eigen::Vector2d p_lidar = r * Eigen::Vector2d(std::cos(a), std::sin(a));
    out.p_ref_true.push_back(between(T_world_lidar0, T_world_lidar) * p_lidar);
  }
  return out;
}

}  // namespace slamprep::testing
