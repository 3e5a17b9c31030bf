#pragma once
// The robot's controller: turns scenario commands into wheel-rate targets. The robot believes
// its NOMINAL geometry, so a (v, w) command becomes wheel rates through the nominal J^-1, exactly
// as on a real robot; wheel-rate commands pass through unchanged. On a closed-loop `track`
// segment the command is corrected by the robot's error from its reference (tracking_law.hpp).

#include <Eigen/Core>
#include <vector>

#include "slamprep/core/diff_drive.hpp"
#include "slamprep/sim/drive/scenario.hpp"

namespace slamprep::sim {

class Controller {
 public:
  Controller(const CommandProfile& profile, const DiffDriveParams& nominal_geometry);

  /// Wheel-rate target (left, right) in rad/s at time t: the feed-forward, open loop.
  Eigen::Vector2d wheelRates(double t_s) const { return toWheelRates(profile_->at(t_s)); }

  /// Wheel-rate target at t for a robot at T_world_base whose reference (the kinematic replay of
  /// the commands) is at T_world_reference: on a closed-loop segment the feed-forward corrected
  /// by the tracking law and capped, elsewhere the feed-forward.
  Eigen::Vector2d wheelRates(double t_s, const SE2& T_world_base,
                             const SE2& T_world_reference) const;

  /// Whether any segment is driven in closed loop (the motion then keeps a reference).
  bool closedLoop() const { return closed_loop_; }

  /// Exact integral of the wheel-rate targets over [t0, t1] (rad): the profile is piecewise
  /// linear and the map to wheel rates is linear, so the trapezoid rule per piece is exact.
  Eigen::Vector2d wheelAngleIncrement(double t0_s, double t1_s) const {
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    profile_->forEachPiece(
        t0_s, t1_s,
        [&](CommandKind kind, const Eigen::Vector2d& c0, const Eigen::Vector2d& c1, double dt_s) {
          sum += 0.5 * dt_s * (toWheelRates({kind, c0}) + toWheelRates({kind, c1}));
        });
    return sum;
  }

  const DiffDriveParams& nominalGeometry() const { return nominal_; }

 private:
  Eigen::Vector2d toWheelRates(const Command& command) const {
    if (command.kind == CommandKind::wheel_rates) return command.value;
    return nominal_.wheelRates(command.value.x(), command.value.y());  // J_nominal^-1 (v, w)
  }

  const CommandProfile* profile_;
  DiffDriveParams nominal_;
  bool closed_loop_ = false;
  std::vector<double> cap_radps_;  ///< per segment: the closed loop's wheel-rate cap
};

}  // namespace slamprep::sim
