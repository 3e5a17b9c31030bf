#include "slamprep/sim/drive/segment_shapes.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

#include "slamprep/core/error.hpp"
#include "slamprep/sim/drive/rng.hpp"

namespace slamprep::sim {

/// Rest-to-rest trapezoid s(t) * peak: s ramps 0 -> 1 in ramp_s, holds, ramps back; its area
/// (integral of s) is area_s. When area_s < ramp_s the peak is lowered to a triangle:
/// p = sqrt(area / ramp), rise time p * ramp, area p^2 * ramp = area.
std::vector<CommandKnot> trapezoid(const Eigen::Vector2d& peak, double ramp_s, double area_s) {
  assert(ramp_s > 0.0 && area_s > 0.0);
  const double p = area_s >= ramp_s ? 1.0 : std::sqrt(area_s / ramp_s);
  const double rise_s = p * ramp_s;
  const double hold_s = area_s / p - rise_s;  // area = p * (rise + hold)
  std::vector<CommandKnot> knots{{0.0, Eigen::Vector2d::Zero()}, {rise_s, p * peak}};
  if (hold_s > 1e-12) knots.push_back({rise_s + hold_s, p * peak});
  knots.push_back({knots.back().t_s + rise_s, Eigen::Vector2d::Zero()});
  return knots;
}

double twistRamp(const Eigen::Vector2d& twist, const AccelerationLimits& limits) {
  return std::max(std::abs(twist.x()) / limits.linear_mps2,
                  std::abs(twist.y()) / limits.angular_radps2);
}

/// Figure eight: `loops` times a full left circle then a full right circle of radius R at speed V.
/// Both components ramp together at the start and end (constant curvature, so the ramps stay on
/// the circle); the w flips between circles are linear ramps centred on the ideal switching time,
/// which keeps the heading integral of every circle exactly 2 pi.
std::vector<CommandKnot> figureEight(double radius_m, double speed_mps, int loops,
                                     const AccelerationLimits& limits, const std::string& at) {
  const double w = speed_mps / radius_m;
  const double ramp_s = twistRamp({speed_mps, w}, limits);
  const double flip_s = 2.0 * w / limits.angular_radps2;
  const double circle_s = 2.0 * std::numbers::pi / w;  // one full turn at w
  if (circle_s < flip_s || circle_s < 0.5 * (ramp_s + flip_s)) {
    throw InputError(at,
                     "circles too short for the acceleration limits (lower speed_mps or raise "
                     "radius_m)");
  }
  std::vector<CommandKnot> knots{{0.0, {0, 0}}, {ramp_s, {speed_mps, w}}};
  double t_switch = circle_s + 0.5 * ramp_s;  // heading of the first circle reaches 2 pi
  double sign = 1.0;
  for (int c = 1; c < 2 * loops; ++c) {
    knots.push_back({t_switch - 0.5 * flip_s, {speed_mps, sign * w}});
    knots.push_back({t_switch + 0.5 * flip_s, {speed_mps, -sign * w}});
    sign = -sign;
    t_switch += circle_s;
  }
  const double end_s = t_switch + 0.5 * ramp_s;  // t_switch: ideal end of the last circle
  knots.push_back({end_s - ramp_s, {speed_mps, sign * w}});
  knots.push_back({end_s, {0, 0}});
  return knots;
}

/// Random smooth twist: knots every interval_s with uniform random targets, each change limited
/// by the acceleration limits, and an envelope that brings the command back to rest at the end.
std::vector<CommandKnot> randomSmooth(double duration_s, double interval_s, double min_speed_mps,
                                      double max_speed_mps, double max_turn_radps,
                                      std::uint64_t seed, const AccelerationLimits& limits) {
  const int n = std::max(2, static_cast<int>(std::lround(duration_s / interval_s)));
  const double dv = limits.linear_mps2 * interval_s;
  const double dw = limits.angular_radps2 * interval_s;
  SplitMix64 rng(seed);
  std::vector<CommandKnot> knots{{0.0, {0, 0}}};
  Eigen::Vector2d prev = Eigen::Vector2d::Zero();
  for (int k = 1; k <= n; ++k) {
    const int steps_left = std::min(k, n - k);  // reachable from rest and back to rest
    const double v_target = min_speed_mps + (max_speed_mps - min_speed_mps) * rng.uniform();
    const double w_target = max_turn_radps * (2.0 * rng.uniform() - 1.0);
    // Clamp to the reachable band first, then to the envelope (the intersection is non-empty).
    double v = std::clamp(v_target, prev.x() - dv, prev.x() + dv);
    double w = std::clamp(w_target, prev.y() - dw, prev.y() + dw);
    v = std::clamp(v, -steps_left * dv, steps_left * dv);
    w = std::clamp(w, -steps_left * dw, steps_left * dw);
    prev = {v, w};
    knots.push_back({k * interval_s, prev});
  }
  knots.back().value.setZero();
  return knots;
}

}  // namespace slamprep::sim
