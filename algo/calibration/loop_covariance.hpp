#pragma once
// Covariance of a calibration whose interval headings were corrected by loop closures
// (algo/matching/loop_closure.hpp). The correction is linear in the intervals' heading errors e
// and the direct matches' errors eps:
//
//   e' = (I - K) e + K_eps eps,   K = D H^-1 A L,   K_eps = D H^-1 A,
//
// H the heading graph's normal matrix over the interval boundaries (the first one held), A the
// loops' boundary incidence, L which intervals each loop spans and D the difference of the two
// boundary corrections of each interval. An estimator whose score is J^T e (J: its heading rows,
// one per interval) then has the score covariance
//
//   f s^2 Y^T Y + s^2 Z^T Z,   Y = (I - K)^T J,   Z = K_eps^T J,
//
// with f the long-run factor of the interval errors (adjacentCorrelationFactor) and s^2 one
// match's heading variance: a direct match errs as much as a consecutive one. Only the matcher's
// part of e is corrected; the wheels' part (slip) is not, so the two terms are weighed by the
// matcher's share of the long-run variance, measured on the loops (matcherShare).

#include <Eigen/Core>
#include <vector>

#include "slamprep/algo/calibration/interval.hpp"

namespace slamprep::algo {

/// The time span of one loop closure: the lidar's heading from t_from to t_to was measured by a
/// direct match, and the intervals in between were corrected to agree with it.
struct LoopSpan {
  double t_from_s = 0.0;
  double t_to_s = 0.0;
};

/// Y and Z of the header comment for heading rows J (intervals.size() x m).
struct LoopCorrectedRows {
  Eigen::MatrixXd Y;  ///< (I - K)^T J, intervals.size() x m
  Eigen::MatrixXd Z;  ///< K_eps^T J, one row per loop that spans at least one interval
};

/// `intervals` in time order; a loop maps to the intervals that start within [t_from, t_to).
LoopCorrectedRows loopCorrectedRows(const std::vector<CalibrationInterval>& intervals,
                                    const std::vector<LoopSpan>& loops, const Eigen::MatrixXd& J);

/// Share a of the heading residuals' long-run variance f s^2 that the loops removed: the
/// matcher's. The rest, the wheels' (slip), stays, and shows in the residuals summed over each
/// loop's span, where the corrected headings agree with the direct match up to its own error s:
///   a = 1 - mean over loops of ((sum of r) ^ 2 - 1) / (N f),  clamped to [0, 1],
/// with r the residuals over s and N the intervals a loop spans. 0 without loops.
double matcherShare(const std::vector<CalibrationInterval>& intervals,
                    const std::vector<LoopSpan>& loops, const std::vector<double>& residuals,
                    double f);

/// The heading rows' score covariance in units of s^2:
///   f [(1 - a) J^T J + a Y^T Y] + Z^T Z,   a = matcherShare(...),
/// which is f J^T J without loops. `residuals`: the heading residuals over s, per interval.
Eigen::MatrixXd loopScoreCovariance(const std::vector<CalibrationInterval>& intervals,
                                    const std::vector<LoopSpan>& loops, const Eigen::MatrixXd& J,
                                    const std::vector<double>& residuals, double f);

}  // namespace slamprep::algo
