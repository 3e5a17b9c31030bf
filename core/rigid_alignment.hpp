#pragma once
// Closed-form rigid alignment of corresponding 2-D points: the point-to-point ICP step and the
// trajectory alignment of the metrics (evo -a) both solve it.

#include <Eigen/Core>
#include <optional>
#include <span>
#include <string>

#include "slamprep/core/se2.hpp"

namespace slamprep {

struct RigidAlignment2D {
  std::optional<SE2> T_q_p;  ///< argmin_T sum |q_i - T p_i|^2; empty when unobservable
  std::string reason;        ///< why T_q_p is empty
};

/// p_i corresponds to q_i. Umeyama (1991) without scale: with centred points p', q', the SVD of
/// H = sum p' q'^T reduces in 2-D to theta = atan2(sum p' x q', sum p' . q') (Eq. (40)-(42); no
/// reflection can arise for an angle), and t = mean(q) - R(theta) mean(p). Refuses fewer than two
/// pairs, and p all coincident or not finite (rotation unobservable).
RigidAlignment2D solveRigid2D(std::span<const Eigen::Vector2d> p,
                              std::span<const Eigen::Vector2d> q);

}  // namespace slamprep
