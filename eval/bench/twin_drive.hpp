#pragma once
// The drive of a twin (docs/twin.md "Drive"): wheel-rate commands that make the simulated robot,
// with the twin's true geometry, follow a recorded trajectory. A kinematic tracker drives the
// exact arcs of the commands (as the simulator's path check does) and picks each knot so that
// the robot reaches the recorded pose one period later; the physics then adds only its slip.

#include <Eigen/Core>
#include <vector>

#include "slamprep/core/diff_drive.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep::eval {

struct TrackParams {
  double period_s = 0.1;            ///< knot spacing of the track segment
  double step_s = 0.01;             ///< kinematic integration step
  double lateral_gain_per_m = 2.0;  ///< heading correction per metre of sideways error ...
  double max_lateral_rad = 0.5;     ///< ... at most this, ...
  double lateral_horizon_s = 1.0;   ///< ... steered out over this long
  double max_wheel_radps = 50.0;    ///< commands are clamped (a matching glitch is not a drive)
  double ramp_s = 0.1;  ///< ... and change by at most max_wheel_radps per ramp_s (acceleration)
};

struct TrackedDrive {
  std::vector<Eigen::Vector2d> wheel_rates;  ///< knot k at (k + 1) period_s; rad/s left, right
  PoseSeries replay;            ///< the kinematic robot at every knot (scenario time, from 0)
  double t0_s = 0.0;            ///< recorded time of scenario time 0
  double rms_position_m = 0.0;  ///< replay against the recording at the knots
  double max_position_m = 0.0;
  double rms_heading_deg = 0.0;
  double distance_m = 0.0;  ///< path length of the recording
  int clamped = 0;          ///< knots whose wheel rates were clamped
};

/// Commands that follow `T_world_base` (recorded poses, increasing stamps) with `geometry`.
TrackedDrive trackTrajectory(const PoseSeries& T_world_base, const DiffDriveParams& geometry,
                             const TrackParams& params = {});

/// The kinematic robot after `dt` of commands moving linearly from c0 to c1 (exact arcs of
/// `steps` sub-steps, the midpoint rate of each).
SE2 driveKinematic(const SE2& T_world_base, const DiffDriveParams& geometry,
                   const Eigen::Vector2d& c0, const Eigen::Vector2d& c1, double dt, int steps);

}  // namespace slamprep::eval
