#pragma once
// 2D scan matching: point-to-point ICP with the closed-form SVD step and point-to-line ICP
// (Censi 2008, PL-ICP) with its exact closed-form step (docs/design.md#scan-matching). Nearest
// neighbours come from a kd-tree; correspondences are gated by distance, then by a robust
// threshold on their residual (optionally also the worst fraction trimmed).
//
// Frames: `ref` points are in the reference lidar frame, `cur` points in the current lidar frame;
// the result T_ref_cur maps current points into the reference frame (p_ref = T_ref_cur * p_cur).

#include <Eigen/Core>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/algo/matching/kdtree.hpp"
#include "slamprep/core/laser_scan.hpp"
#include "slamprep/core/se2.hpp"

namespace slamprep::algo {

struct IcpParams {
  /// Correspondence-and-solve rounds before giving up.
  int max_iterations = 50;
  /// Gating: a pair farther apart than this (after applying the estimate) is no correspondence.
  double max_correspondence_distance_m = 0.5;
  /// Robust gate: each round drops the pairs whose residual exceeds this many robust sigmas,
  /// sigma = 1.4826 * median |residual| of the gated pairs (0 = off). It drops almost no Gaussian
  /// residual and every gross outlier, where a fixed fraction (below) also drops good pairs that
  /// disagree with the current estimate and so pulls the result toward the first guess.
  double outlier_sigmas = 0.0;
  /// Trimming: this fraction of the remaining pairs, the worst ones, is dropped each round.
  double trim_fraction = 0.1;
  /// Converged when a round moves the estimate by less than this translation (0.1 mm: ten
  /// times below what 1 cm range noise lets a 720-beam match resolve) ...
  double translation_tolerance_m = 1e-4;
  /// ... and less than this rotation (0.05 mm at 5 m).
  double rotation_tolerance_rad = 1e-5;
  /// Coarse to fine: only every n-th current point is matched while the rounds still move the
  /// estimate by more than coarse_until_m or coarse_until_rad (1 = always all points).
  std::size_t coarse_stride = 4;
  double coarse_until_m = 0.002;
  double coarse_until_rad = 0.001;
  /// Fewer surviving correspondences than this: refuse (too little overlap).
  std::size_t min_inliers = 20;
  /// Point-to-line: neighbours in `ref` (the point itself included) whose line is fitted.
  std::size_t line_neighbors = 5;
  /// Point-to-line: neighbours farther than this from the point are left out of its line fit.
  double line_max_radius_m = 0.3;
  /// Point-to-line: a fit is a line only if sqrt(lambda_min / lambda_max) is below this.
  double line_max_thickness = 0.2;
  /// Covariance: each principal variance is capped here, so degenerate directions (a corridor)
  /// show up as huge, never as inf or NaN.
  double max_variance = 1e6;
};

struct IcpResult {
  SE2 T_ref_cur;
  bool converged = false;
  int iterations = 0;
  std::size_t inliers = 0;      ///< correspondences used in the last round
  double rms_residual_m = 0.0;  ///< RMS point-to-point or point-to-line distance of the inliers
  /// Covariance of (x, y, yaw) of T_ref_cur: sigma^2 (J^T J)^-1 with sigma^2 estimated from the
  /// residuals (Gauss-Newton / Hessian approximation). Optimistic: ignores correlated errors.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();
  std::string reason;  ///< why it did not converge; empty when it did
};

/// A reference point set prepared once (kd-tree, and line normals when asked for), so that many
/// scans can be matched against one keyframe without rebuilding anything.
class IcpReference {
 public:
  /// `with_normals` fits a line through each point's neighbours (needed by point-to-line).
  IcpReference(Points2 ref, const IcpParams& params, bool with_normals);

  const Points2& points() const { return tree_.points(); }
  const KdTree2& tree() const { return tree_; }
  bool hasNormals() const { return !normals_.empty(); }
  /// Unit normal of the line through point i; (0, 0) where the neighbourhood is no line.
  const Eigen::Vector2d& normal(std::size_t i) const { return normals_[i]; }
  /// A point on that line: the centroid of the neighbours it was fitted to.
  const Eigen::Vector2d& linePoint(std::size_t i) const { return line_points_[i]; }

 private:
  KdTree2 tree_;
  std::vector<Eigen::Vector2d> normals_;
  std::vector<Eigen::Vector2d> line_points_;
};

/// Point-to-point ICP: nearest neighbours, closed-form SVD step (Arun/Umeyama), repeat.
IcpResult matchPointToPoint(const Points2& ref, const Points2& cur, const SE2& T_ref_cur_guess,
                            const IcpParams& params);
IcpResult matchPointToPoint(const IcpReference& ref, const Points2& cur, const SE2& T_ref_cur_guess,
                            const IcpParams& params);

/// Point-to-line ICP (Censi 2008): each current point is pulled onto the line fitted through its
/// nearest reference point; each round solves the exact minimiser in closed form.
IcpResult matchPointToLine(const Points2& ref, const Points2& cur, const SE2& T_ref_cur_guess,
                           const IcpParams& params);
IcpResult matchPointToLine(const IcpReference& ref, const Points2& cur, const SE2& T_ref_cur_guess,
                           const IcpParams& params);

/// One closed-form point-to-point step: the T minimising sum |q_i - T p_i|^2 (Eq. lecture ICP).
/// Needs at least two pairs; returns nullopt when the pairs are degenerate.
std::optional<SE2> alignPointToPoint(const Points2& p, const Points2& q);

}  // namespace slamprep::algo
