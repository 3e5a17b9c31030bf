#pragma once
// People about the robot (docs/simulate.md "People"): discs at the lidar's height that wander
// about it, each keeping an offset from the robot that drifts, so the lidar sees something that
// is not where it was a few seconds before. Real recordings hold such returns (students walking
// beside their robot, doors, things moved); a matcher pulled by them errs, a world of still
// walls has none.

#include <Eigen/Core>
#include <cstdint>
#include <optional>
#include <vector>

#include "slamprep/sim/drive/rng.hpp"

namespace slamprep::sim {

struct PeopleConfig {
  int count = 0;               ///< people about the robot (0: none)
  double distance_m = 2.0;     ///< sigma, per axis, of a person's offset from the robot
  double correlation_s = 5.0;  ///< how long a person keeps about the same offset
  double radius_m = 0.12;      ///< a person's legs at the lidar's height, as one disc
};

/// Person j's offset o_j from the robot (world frame) is an Ornstein-Uhlenbeck process sampled
/// every kStepS, a = exp(-kStepS / correlation_s):
///   o_j(k + 1) = a o_j(k) + sqrt(1 - a^2) distance_m n,  n ~ N(0, I),  o_j(0) ~ N(0, distance_m^2
///   I)
/// linear between the samples, and never nearer the robot than kNearestM (people keep out of
/// its way). The samples are drawn on a fixed grid from the seed alone, so the people are the same
/// whatever asks for them when.
class People {
 public:
  static constexpr double kStepS = 0.05;
  static constexpr double kNearestM = 0.6;
  People(const PeopleConfig& config, std::uint64_t seed);
  /// Range along the ray from origin (unit direction dir, world frame) to the nearest person at
  /// t_s, with the robot's base at robot_world; nullopt for none within max_range_m. t_s must
  /// not decrease from call to call.
  std::optional<double> castRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& dir,
                                const Eigen::Vector2d& robot_world, double t_s, double max_range_m);

 private:
  void advanceTo(double t_s);  // samples k and k + 1 bracket t_s
  std::vector<Eigen::Vector2d> draw();

  PeopleConfig config_;
  SplitMix64 rng_;
  double a_ = 0.0;
  std::int64_t k_ = 0;  ///< index of `before_`
  std::vector<Eigen::Vector2d> before_, after_;
};

}  // namespace slamprep::sim
