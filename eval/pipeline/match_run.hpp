#pragma once
// Scan matching on a dataset (`slamprep match`, and the bench's "matching" figures): the matches
// of algo::matchConsecutiveScans, their error against the true lidar motion, matches.jsonl.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slamprep/algo/calibration/dataset_motion.hpp"
#include "slamprep/core/dataset.hpp"
#include "slamprep/eval/metrics/error_stats.hpp"

namespace slamprep::eval {

/// Error of the converged matches against the true lidar motion: err = (T_w_ref^-1 T_w_cur)^-1
/// T_ref_cur with the true T_world_lidar at both first beams, T_ref_cur taken as the step of the
/// chain (algo::chainMatches) that calibration cuts its intervals from.
struct ScanMatchError {
  std::size_t pairs = 0;      ///< matches attempted
  std::size_t converged = 0;  ///< of which converged
  std::size_t compared = 0;   ///< converged with truth at both ends
  ErrorStats translation_m;   ///< |t(err)| (ok = false when nothing was compared)
  ErrorStats rotation_deg;    ///< |yaw(err)|
};

/// `T_world_lidar_true`: e.g. algo::lidarPosesFromGroundTruth (empty: nothing compared).
ScanMatchError scanMatchError(const std::vector<algo::ScanMatch>& matches,
                              const PoseSeries& T_world_lidar_true);

/// The matches of a dataset and their error against its ground truth (when it has truth).
struct MatchRun {
  std::vector<algo::ScanMatch> matches;
  ScanMatchError error;
};
MatchRun matchDataset(const Dataset& dataset, const algo::ScanMotionParams& params);

/// matches.jsonl (docs/deskew.md): one object per pair, stamp_ref, stamp_cur, T_ref_cur, converged,
/// iterations, inliers, rms_m, covariance (row-major 3x3), reason.
std::string formatMatches(const std::vector<algo::ScanMatch>& matches);

/// One matches.jsonl object: the stamps, T_ref_cur, convergence, inliers, RMS, the 3x3
/// covariance (row-major) and the reason (docs/matching.md).
nlohmann::ordered_json matchLine(double stamp_ref_s, double stamp_cur_s, const algo::IcpResult& m);

}  // namespace slamprep::eval
