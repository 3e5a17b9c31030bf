#pragma once
// The robot's controller: turns scenario commands into wheel-rate targets. The robot believes
// its NOMINAL geometry, so a (v, w) command becomes wheel rates through the nominal J^-1, exactly
// as on a real robot; wheel-rate commands pass through unchanged.

#include <Eigen/Core>

#include "slamprep/core/diff_drive.hpp"
#include "slamprep/sim/drive/scenario.hpp"

namespace slamprep::sim {

class Controller {
 public:
  Controller(const CommandProfile& profile, const DiffDriveParams& nominal_geometry)
      : profile_(&profile), nominal_(nominal_geometry) {}

  /// Wheel-rate target (left, right) in rad/s at time t.
  Eigen::Vector2d wheelRates(double t_s) const { return toWheelRates(profile_->at(t_s)); }

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
};

}  // namespace slamprep::sim
