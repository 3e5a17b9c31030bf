#include "slamprep/eval/bench/twin_drive.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "slamprep/core/odometry.hpp"

namespace slamprep::eval {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;
/// How much of the last knot's error the next knot corrects beyond the needed mean: 0.5 halves
/// the error every period without ringing (the knot's command acts as the mean of two knots).
constexpr double kKnotDamping = 0.5;

SE2 recordedAt(const PoseSeries& T_world_base, double t_s) {
  const double t = std::clamp(t_s, T_world_base.frontStamp(), T_world_base.backStamp());
  return *T_world_base.at(t);
}

/// The mean body twist that takes the robot from T_world_base to T_world_target in dt, with
/// the heading turned toward a target beside the path (the unicycle cannot move sideways).
Eigen::Vector2d meanTwist(const SE2& T_world_base, const SE2& T_world_target, double dt,
                          const TrackParams& p) {
  const SE2 e = between(T_world_base, T_world_target);
  const double lateral = std::clamp(p.lateral_gain_per_m * e.y * (e.x >= 0.0 ? 1.0 : -1.0),
                                    -p.max_lateral_rad, p.max_lateral_rad);
  // The sideways error is steered out over lateral_horizon_s, not within one knot: the matched
  // trajectory's centimetres of sideways jitter otherwise turned the robot at up to 5 rad/s.
  const double share = std::min(1.0, dt / p.lateral_horizon_s);
  return {e.x / dt, (e.yaw + share * lateral * std::min(1.0, std::abs(e.x) / 0.01)) / dt};
}

/// The knot within the wheel-rate and acceleration limits (both scaled, so the turn's ratio stays).
Eigen::Vector2d limitKnot(Eigen::Vector2d next, const Eigen::Vector2d& last, const TrackParams& p,
                          TrackedDrive& drive) {
  bool clamped = false;
  const double peak = next.cwiseAbs().maxCoeff();
  if (peak > p.max_wheel_radps) {
    next *= p.max_wheel_radps / peak;
    clamped = true;
  }
  const double max_change = p.max_wheel_radps * p.period_s / p.ramp_s;
  const double change = (next - last).cwiseAbs().maxCoeff();
  if (change > max_change) {
    next = last + (next - last) * (max_change / change);
    clamped = true;
  }
  if (clamped) ++drive.clamped;
  return next;
}

}  // namespace

SE2 driveKinematic(const SE2& T_world_base, const DiffDriveParams& geometry,
                   const Eigen::Vector2d& c0, const Eigen::Vector2d& c1, double dt, int steps) {
  SE2 T = T_world_base;
  const double h = dt / steps;
  for (int s = 0; s < steps; ++s) {
    const Eigen::Vector2d mid = c0 + (c1 - c0) * ((s + 0.5) / steps);  // exact for linear rates
    T = T * wheelIncrement(geometry, mid.x() * h, mid.y() * h);
  }
  return T;
}

TrackedDrive trackTrajectory(const PoseSeries& T_world_base, const DiffDriveParams& geometry,
                             const TrackParams& p) {
  TrackedDrive drive;
  if (T_world_base.size() < 2) return drive;
  drive.t0_s = T_world_base.frontStamp();
  for (std::size_t i = 1; i < T_world_base.size(); ++i)
    drive.distance_m +=
        (T_world_base[i].value.translation() - T_world_base[i - 1].value.translation()).norm();
  const double span_s = T_world_base.backStamp() - drive.t0_s;
  const auto knots = static_cast<std::size_t>(std::ceil(span_s / p.period_s));
  const int steps = std::max(1, static_cast<int>(std::lround(p.period_s / p.step_s)));
  SE2 T = T_world_base[0].value;
  Eigen::Vector2d last = Eigen::Vector2d::Zero();
  drive.replay.push_back(0.0, T);
  double sq_pos = 0.0, sq_yaw = 0.0;
  for (std::size_t k = 1; k <= knots; ++k) {
    const double tau = double(k) * p.period_s;
    const SE2 target = recordedAt(T_world_base, drive.t0_s + tau);
    const Eigen::Vector2d twist = meanTwist(T, target, p.period_s, p);
    const Eigen::Vector2d mean = geometry.wheelRates(twist.x(), twist.y());
    const Eigen::Vector2d next = limitKnot(mean + kKnotDamping * (mean - last), last, p, drive);
    T = driveKinematic(T, geometry, last, next, p.period_s, steps);
    last = next;
    drive.wheel_rates.push_back(next);
    drive.replay.push_back(tau, T);
    const SE2 err = between(target, T);
    const double d = err.translation().norm();
    sq_pos += d * d;
    sq_yaw += err.yaw * err.yaw;
    drive.max_position_m = std::max(drive.max_position_m, d);
  }
  if (knots > 0) {
    drive.rms_position_m = std::sqrt(sq_pos / double(knots));
    drive.rms_heading_deg = std::sqrt(sq_yaw / double(knots)) * kDegPerRad;
  }
  return drive;
}

}  // namespace slamprep::eval
