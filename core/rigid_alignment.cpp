#include "slamprep/core/rigid_alignment.hpp"

#include <cmath>

namespace slamprep {

RigidAlignment2D solveRigid2D(std::span<const Eigen::Vector2d> p,
                              std::span<const Eigen::Vector2d> q) {
  if (p.size() != q.size() || p.size() < 2) return {{}, "need at least two corresponding points"};
  const double n = static_cast<double>(p.size());
  Eigen::Vector2d p_mean = Eigen::Vector2d::Zero(), q_mean = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) {
    p_mean += p[i] / n;
    q_mean += q[i] / n;
  }
  double dot = 0.0, cross = 0.0, spread = 0.0;  // sum p'.q', sum p' x q', sum |p'|^2
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Eigen::Vector2d pc = p[i] - p_mean, qc = q[i] - q_mean;
    dot += pc.dot(qc);
    cross += pc.x() * qc.y() - pc.y() * qc.x();
    spread += pc.squaredNorm();
  }
  if (!(spread > 1e-18 * n) || !std::isfinite(dot + cross))
    return {{}, "points coincide (or are not finite): rotation unobservable"};
  const double theta = std::atan2(cross, dot);
  const Eigen::Vector2d t = q_mean - SE2(0.0, 0.0, theta).rotation() * p_mean;
  return {SE2(t.x(), t.y(), theta), ""};
}

}  // namespace slamprep
