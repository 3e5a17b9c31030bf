#pragma once
// Knots of the rest-to-rest segment shapes a scenario is built from: trapezoid ramps, the figure
// eight and the random smooth twist, each within the acceleration limits.

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "slamprep/sim/drive/command_profile.hpp"

namespace slamprep::sim {

/// Rest-to-rest trapezoid towards `peak`: ramps of ramp_s, area (of the unit shape) area_s; a
/// lower triangle when area_s < ramp_s.
std::vector<CommandKnot> trapezoid(const Eigen::Vector2d& peak, double ramp_s, double area_s);

/// Ramp time of a twist command from rest under the limits (both components ramp together).
double twistRamp(const Eigen::Vector2d& twist, const AccelerationLimits& limits);

/// Figure eight: `loops` times a full left circle then a full right circle. Throws
/// InputError(at, ...) when the circles are too short for the acceleration limits.
std::vector<CommandKnot> figureEight(double radius_m, double speed_mps, int loops,
                                     const AccelerationLimits& limits, const std::string& at);

/// Random smooth twist from rest back to rest, a knot every interval_s; the seed fixes the knots.
std::vector<CommandKnot> randomSmooth(double duration_s, double interval_s, double min_speed_mps,
                                      double max_speed_mps, double max_turn_radps,
                                      std::uint64_t seed, const AccelerationLimits& limits);

}  // namespace slamprep::sim
