#pragma once
// A measured relative pose between two instants of one trajectory (the "relations" of the SLAM
// benchmark of Kümmerle et al. 2009, docs/score.md).

#include <cstddef>

#include "slamprep/core/se2.hpp"

namespace slamprep {

/// T_1_2 = T_w_base(t1)^-1 T_w_base(t2): where the robot is at t2, seen from where it was at t1.
struct PoseRelation {
  double t1_s = 0.0;
  double t2_s = 0.0;
  SE2 T_1_2;
  std::size_t line = 0;  ///< 1-based line of the file it was read from (0: not from a file)
};

}  // namespace slamprep
