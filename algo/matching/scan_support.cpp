#include "slamprep/algo/matching/scan_support.hpp"

#include <algorithm>
#include <cmath>

namespace slamprep::algo {

ScanSupport scanSupport(const IcpReference& ref, const Points2& cur, const SE2& T_ref_cur,
                        double inlier_distance_m) {
  ScanSupport s;
  s.points = cur.size();
  const double c_sq = inlier_distance_m * inlier_distance_m;
  if (cur.empty() || ref.points().empty()) {
    s.cost_m2 = c_sq;
    return s;
  }
  const Eigen::Matrix2d R = T_ref_cur.rotation();
  const Eigen::Vector2d t = T_ref_cur.translation();
  double cost = 0.0, inlier_sq = 0.0;
  for (const Eigen::Vector2d& p : cur) {
    const Eigen::Vector2d p_ref = R * p + t;
    const Neighbor nn = *ref.tree().nearest(p_ref);  // the tree is not empty
    double r_sq = nn.distance_sq_m2;
    if (ref.hasNormals() && !ref.normal(nn.index).isZero())
      r_sq = std::pow(ref.normal(nn.index).dot(p_ref - ref.linePoint(nn.index)), 2);
    // The line residual only counts near the line's own points: far away it would be zero
    // along the line's whole extension.
    if (nn.distance_sq_m2 > 4.0 * c_sq) r_sq = std::max(r_sq, c_sq);
    if (nn.distance_sq_m2 <= 25.0 * c_sq) ++s.overlapping;
    cost += std::min(r_sq, c_sq);
    if (r_sq < c_sq) {
      ++s.inliers;
      inlier_sq += r_sq;
    }
  }
  s.cost_m2 = cost / double(cur.size());
  s.rms_inlier_m = s.inliers == 0 ? 0.0 : std::sqrt(inlier_sq / double(s.inliers));
  return s;
}

}  // namespace slamprep::algo
