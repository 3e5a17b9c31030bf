#pragma once
// The estimate VICP and odom+ICP share (internal to algo/deskew): both scans of a match de-skewed
// with one correction rate eps, the current matched against the previous by ICP, eps re-estimated
// from the match, until the scan-end pose settles.

#include <Eigen/Core>
#include <optional>
#include <string>

#include "slamprep/algo/deskew/method.hpp"

namespace slamprep::algo {

/// One scan of a joint estimate: its beams, times (reference at its first beam), and base
/// trajectory T_L0_L(t) (odometry, or a single identity knot) that exp(eps (t - t_first))
/// multiplies.
struct CorrectedScan {
  const LaserScan* scan = nullptr;
  ScanTimes t;
  Trajectory base;
};

/// base(t_k) * exp(eps (t_k - t_first)) at every knot; with a single identity base knot, a
/// constant twist eps over the whole scan.
Trajectory correctedKnots(const CorrectedScan& s, const Eigen::Vector3d& eps);

/// The outcome of a joint estimate: the correction rate and the last good match.
struct JointEstimate {
  Eigen::Vector3d eps = Eigen::Vector3d::Zero();
  std::optional<IcpResult> match;
  int rounds = 0;
  std::string failure;  ///< the ICP failure that ended it, if one did
};

/// E = T_prev_cur_pred^-1 T_prev_cur_icp is the correction accumulated between the first beams
/// (T_prev_cur_pred: the motion the bases predict), eps = log(E) / dt with the error growing
/// linearly in time.
JointEstimate estimateJointly(const CorrectedScan& prev, const CorrectedScan& cur,
                              const SE2& T_prev_cur_pred, const Eigen::Vector3d& eps_guess,
                              const DeskewParams& params);

/// The previous scan's times, reference at its first beam.
ScanTimes previousTimes(const PreviousScan& prev);

/// The same times with the reference moved to the first beam (joint estimates work there).
ScanTimes atFirstBeam(ScanTimes t);

}  // namespace slamprep::algo
