#pragma once
// Synthetic calibration intervals from known geometry, generated with core's exact arc model
// (wheelIncrement), independent of the algo/ motion model under test.

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <vector>

#include "slamprep/algo/calibration/interval.hpp"
#include "slamprep/core/odometry.hpp"

namespace slamprep::algo::testing {

enum class Driving { kMixed, kStraight, kSpin };

struct SyntheticSpec {
  DiffDriveParams truth{0.098, 0.102, 0.52};
  SE2 T_base_lidar{0.12, -0.04, 0.3};
  int intervals = 60;
  int steps_per_interval = 30;
  double dt_s = 0.01;
  Driving driving = Driving::kMixed;
  // Noise added to the measured lidar motion, in the lidar frame at the interval's start. The
  // axes differ so that a method that mixes up the noise frame (or assumes it isotropic) shows.
  double sigma_x_m = 0.0;        ///< along the lidar's x axis
  double sigma_y_m = 0.0;        ///< along the lidar's y axis
  double sigma_theta_rad = 0.0;  ///< on the rotation
  /// Scan-to-scan matching: each interval's noise is (a_k + R w_{k+1} - w_k) / sqrt(3) per axis,
  /// a_k, w_k unit Gaussians (w_k: the error of the scan at the interval's start in its frame,
  /// R the interval's rotation: translation rows only, the sigmas scale each axis), so
  /// consecutive intervals' errors correlate with rho = -1/3 and the variance stays sigma^2.
  bool shared_scans = false;
  /// Consecutive intervals driving the same manoeuvre (scan matches are short: the motion changes
  /// slowly from one to the next).
  int intervals_per_manoeuvre = 1;
  /// Sideslip k (s): the base also moves sideways at v_y = k v w.
  double sideslip_s = 0.0;
  /// Slip in turns: the rotation's noise sigma is sqrt(sigma_theta^2 + (turn_slip theta)^2),
  /// theta the interval's true rotation (the wheels count (1 + u) of their turn, u of sigma
  /// turn_slip), so it grows with the turn; the translation's does not.
  double turn_slip = 0.0;
  unsigned seed = 1;
};

/// The true base motion of one step: the exact arc, plus the sideslip k ds dth / dt sideways.
inline SE2 trueStep(const SyntheticSpec& spec, const EncoderStep& step) {
  if (spec.sideslip_s == 0.0)
    return wheelIncrement(spec.truth, step.dphi_left_rad, step.dphi_right_rad);
  const DiffDriveParams& g = spec.truth;
  const double ds =
      0.5 * (g.radius_left_m * step.dphi_left_rad + g.radius_right_m * step.dphi_right_rad);
  const double dth =
      (g.radius_right_m * step.dphi_right_rad - g.radius_left_m * step.dphi_left_rad) /
      g.wheel_base_m;
  return SE2::exp({ds, spec.sideslip_s * ds * dth / step.dt_s, dth});
}

/// Wheel rates (rad/s) of interval k at step j: curves both ways, spins, near-straight driving,
/// with the speed varying inside the interval so constant-speed shortcuts would be wrong.
inline Eigen::Vector2d wheelRates(const SyntheticSpec& spec, int k, int j) {
  const double wobble = 1.0 + 0.3 * std::sin(0.37 * j + 1.3 * k);
  Eigen::Vector2d w;
  switch (spec.driving) {
    case Driving::kStraight:
      w = {6.0, 6.0};
      break;
    case Driving::kSpin:
      w = {-4.0, 4.0};
      break;
    default:
      switch ((k / spec.intervals_per_manoeuvre) % 4) {
        case 0:
          w = {3.0, 6.0};
          break;  // curve left
        case 1:
          w = {6.0, 2.5};
          break;  // curve right
        case 2:
          w = {-4.0, 4.5};
          break;  // spin
        default:
          w = {6.0, 6.5};
          break;  // nearly straight
      }
  }
  return wobble * w;
}

inline std::vector<CalibrationInterval> makeIntervals(const SyntheticSpec& spec) {
  std::mt19937_64 rng(spec.seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::vector<CalibrationInterval> out;
  double t = 0.0;
  // Three unit Gaussians drawn in order (argument evaluation order is unspecified).
  const auto draw3 = [&] {
    Eigen::Vector3d v;
    for (int i = 0; i < 3; ++i) v(i) = gauss(rng);
    return v;
  };
  Eigen::Vector3d w_start = spec.shared_scans ? draw3() : Eigen::Vector3d::Zero();
  for (int k = 0; k < spec.intervals; ++k) {
    CalibrationInterval interval;
    interval.t_start_s = t;
    SE2 o;  // true T_baseStart_baseEnd
    for (int j = 0; j < spec.steps_per_interval; ++j) {
      const Eigen::Vector2d w = wheelRates(spec, k, j);
      EncoderStep step{spec.dt_s, w.x() * spec.dt_s, w.y() * spec.dt_s};
      interval.steps.push_back(step);
      o = o * trueStep(spec, step);
      t += spec.dt_s;
    }
    interval.t_end_s = t;
    const SE2 sm = spec.T_base_lidar.inverse() * o * spec.T_base_lidar;
    Eigen::Vector3d unit = draw3();
    if (spec.shared_scans) {
      const Eigen::Vector3d w_end = draw3();
      Eigen::Vector3d w_end_here = w_end;  // the end scan's error, seen from the start frame
      w_end_here.head<2>() = Eigen::Rotation2D<double>(sm.yaw).toRotationMatrix() * w_end.head<2>();
      unit = (unit + w_end_here - w_start) / std::sqrt(3.0);
      w_start = w_end;
    }
    const double nx = spec.sigma_x_m * unit.x(), ny = spec.sigma_y_m * unit.y();
    const double nth = std::hypot(spec.sigma_theta_rad, spec.turn_slip * o.yaw) * unit.z();
    interval.T_lidarStart_lidarEnd = SE2(sm.x + nx, sm.y + ny, sm.yaw + nth);
    out.push_back(std::move(interval));
  }
  return out;
}

/// Relative error |a - b| / |b|.
inline double rel(double a, double b) {
  return std::abs(a - b) / std::abs(b);
}

}  // namespace slamprep::algo::testing
