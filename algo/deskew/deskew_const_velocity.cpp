// Constant velocity (KISS-ICP): the lidar keeps the twist xi it had between the previous two
// scans, T_Lref_L(t) = exp(xi (t - t_ref)); DeskewSequence estimates xi after every scan.
#include "slamprep/algo/deskew/method.hpp"

namespace slamprep::algo {

Trajectory constVelocityKnots(const MethodCall& call) {
  const auto& previous = call.in.previous;
  if (!previous || !previous->twist_lidar) {
    call.result.warnings.push_back("const-velocity: no previous motion yet; scan left as measured");
    call.result.as_measured = true;
    return constantTwistKnots(Eigen::Vector3d::Zero(), call.t);
  }
  return constantTwistKnots(*previous->twist_lidar, call.t);
}

}  // namespace slamprep::algo
