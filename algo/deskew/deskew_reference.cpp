// The two references every other method is judged between:
//   none:   T_Lref_L(t) = I, the points as measured (the floor);
//   oracle: T_Lref_L(t) = (T_world_base(t_ref) T_base_lidar)^-1 T_world_base(t) T_base_lidar with
//           the true poses, interpolated between their samples (the ceiling).
#include "slamprep/algo/deskew/method.hpp"

namespace slamprep::algo {

Trajectory noneKnots(const MethodCall& call) {
  call.result.as_measured = true;
  return identityKnot(call.t.ref_s);
}

Trajectory oracleKnots(const MethodCall& call) {
  return relativeTo(lidarKnots(call, call.in.groundtruth, call.in.T_base_lidar, "ground truth"),
                    call.t.ref_s);
}

}  // namespace slamprep::algo
