#pragma once
// What every de-skew method shares (internal to algo/deskew): the call it receives, the way it
// refuses, and the knot builders more than one method uses. A method returns the lidar motion
// over the scan as knots of T_Lref_L(t); deskew() moves the beams with them (beam_transform.hpp).

#include <Eigen/Core>
#include <string>
#include <string_view>

#include "slamprep/algo/deskew/beam_transform.hpp"
#include "slamprep/algo/deskew/deskew.hpp"

namespace slamprep::algo {

/// The scan's time span and the reference time.
struct ScanTimes {
  double first_s = 0.0, last_s = 0.0, ref_s = 0.0;
};
ScanTimes scanTimes(const LaserScan& scan, bool stamp_is_last_beam, ReferenceTime reference);

/// Thrown by a method that cannot run, with its reason (caught in deskew(), never escapes).
struct Refusal {
  DeskewRefusal code;
  std::string reason;
};

/// One call of a method: what it reads, and the result it may annotate (match, rounds, warnings).
struct MethodCall {
  DeskewMethod method;
  const LaserScan& scan;
  ScanTimes t;
  const DeskewInputs& in;
  const DeskewParams& params;
  DeskewResult& result;

  /// Refuses with "<method> needs <what>, none was given" unless `given`.
  void need(bool given, std::string_view what) const;
};

/// Six decimals, for messages.
std::string fmt(double x);

/// Samples of `poses` (times T_base_lidar) from the one at or before t.first_s to the one at or
/// after t.last_s: the knots of T_X_L(t). Refuses when they do not bracket the scan or have a
/// gap longer than max_gap_s inside it.
Trajectory lidarKnots(const PoseSeries& poses, const SE2& T_base_lidar, const ScanTimes& t,
                      const LaserScan& scan, bool stamp_is_last_beam, double max_gap_s,
                      std::string_view what);
/// lidarKnots() of the call's own scan.
Trajectory lidarKnots(const MethodCall& call, const PoseSeries& poses, const SE2& T_base_lidar,
                      std::string_view what);

/// Constant twist over the scan: T_Lref_L(t) = exp(twist (t - t_ref)), as two knots.
Trajectory constantTwistKnots(const Eigen::Vector3d& twist_per_s, const ScanTimes& t);

/// The identity at t: a single knot (no motion).
Trajectory identityKnot(double t);

// The methods, one family per file; each returns T_Lref_L knots or throws a Refusal.
Trajectory noneKnots(const MethodCall& call);           // deskew_reference.cpp
Trajectory oracleKnots(const MethodCall& call);         // deskew_reference.cpp
Trajectory odomLinearKnots(const MethodCall& call);     // deskew_odometry.cpp
Trajectory odomQuadraticKnots(const MethodCall& call);  // deskew_odometry.cpp
Trajectory imuKnots(const MethodCall& call);            // deskew_imu.cpp
Trajectory constVelocityKnots(const MethodCall& call);  // deskew_const_velocity.cpp
Trajectory vicpKnots(const MethodCall& call);           // deskew_vicp.cpp
Trajectory odomIcpKnots(const MethodCall& call);        // deskew_odom_icp.cpp

}  // namespace slamprep::algo
