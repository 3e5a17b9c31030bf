#pragma once
// The relation-based metric of Kümmerle et al., "On measuring the accuracy of SLAM algorithms",
// Autonomous Robots 27(4), 2009 (docs/score.md): each relation, a reference relative pose
// delta*_ij between the robot at t_i and at t_j, is compared with the estimate's relative pose
// delta_ij = P(t_i)^-1 P(t_j); errors are per relation, so no global alignment is needed.

#include <string>
#include <vector>

#include "slamprep/core/pose_relation.hpp"
#include "slamprep/core/time_series.hpp"
#include "slamprep/eval/metrics/error_stats.hpp"

namespace slamprep::eval {

struct RelationErrorParams {
  /// A relation stamp t takes the estimate interpolated (geodesically) between the samples
  /// t_a <= t <= t_b around it, used only when t equals a sample or max(t - t_a, t_b - t) <= this;
  /// else the relation is skipped as uncovered. An estimate at the scan stamps the relations name
  /// matches exactly; 0.5 s bridges the usual ODOM spacing of the benchmark logs (99th percentile
  /// 0.15-0.99 s) but not their dropouts (up to 3.1 s).
  double max_time_difference_s = 0.5;
  /// Relations with |t_j - t_i| below this form the short subset (reported separately).
  double short_relation_s = 5.0;
};

/// Statistics of one set of relations (population std, as ErrorStats).
struct RelationStats {
  ErrorStats translation_m;      ///< |trans(E_ij)|
  ErrorStats translation_sq_m2;  ///< |trans(E_ij)|^2
  ErrorStats rotation_deg;       ///< |rot(E_ij)|, degrees
  ErrorStats rotation_sq_deg2;   ///< rot(E_ij)^2, degrees^2
};

struct RelationErrorResult {
  bool ok = false;
  std::string reason;
  std::size_t relations = 0;  ///< given
  std::size_t uncovered = 0;  ///< skipped: a stamp the estimate does not cover
  RelationStats all;          ///< every scored relation
  RelationStats short_span;   ///< scored relations with |t_j - t_i| < short_relation_s
  std::size_t short_count = 0;
  std::vector<std::size_t> scored;  ///< index into the input of every scored relation
  std::vector<double> translation_errors_m;
  std::vector<double> rotation_errors_deg;  ///< signed, wrapped to (-180, 180]
};

/// The metric of Kümmerle et al. 2009 per relation: E_ij = delta*_ij^-1 delta_ij (the paper's
/// delta_ij ⊖ delta*_ij), trans(E_ij) = |t(delta_ij) - t(delta*_ij)|, rot(E_ij) =
/// wrap(theta(delta_ij) - theta(delta*_ij)).
RelationErrorResult relationError(const PoseSeries& estimate,
                                  const std::vector<PoseRelation>& relations,
                                  const RelationErrorParams& params = {});

}  // namespace slamprep::eval
