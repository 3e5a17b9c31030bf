#pragma once
// Measured lidar motion from a dataset: from ground truth (an oracle run) or from matching
// consecutive scans, the one scan-to-scan loop that `slamprep match`, `slamprep calibrate` and
// the bench share.

#include <optional>
#include <vector>

#include "slamprep/algo/calibration/interval.hpp"
#include "slamprep/algo/calibration/umbmark.hpp"
#include "slamprep/algo/deskew/deskew.hpp"
#include "slamprep/algo/matching/icp.hpp"
#include "slamprep/core/dataset.hpp"

namespace slamprep::algo {

/// T_world_lidar at every scan's first beam from the true base poses and the dataset's mount
/// (the scan's own true pose when its stamp is the first beam, else the interpolated truth).
/// Empty when the dataset has no ground truth.
PoseSeries lidarPosesFromGroundTruth(const Dataset& dataset, bool stamp_is_last_beam = false);

/// Nominal odometry between t0 and t1 seen by the lidar: T_base_lidar^-1 T_t0_t1 T_base_lidar
/// (the guess of every odometry-guided match); nullopt where the odometry does not cover both.
std::optional<SE2> odometryLidarMotion(const Dataset& dataset, double t0_s, double t1_s);

/// How consecutive scans are matched.
enum class ScanMatcher {
  kIcp,   ///< point-to-line ICP on the points given (as measured, or de-skewed beforehand)
  kVicp,  ///< both scans de-skewed with one twist estimated jointly with the match
};

/// Where each match's initial guess comes from.
enum class MotionGuess {
  kOdometry,          ///< nominal odometry through the dataset's mount (identity where none)
  kConstantVelocity,  ///< the last converged match's twist (all a lidar-only log has)
};

struct ScanMotionParams {
  ScanMatcher matcher = ScanMatcher::kIcp;
  MotionGuess guess = MotionGuess::kOdometry;
  bool stamp_is_last_beam = false;  ///< the scans' stamps mark their last beam
  DeskewParams deskew;              ///< `deskew.icp` is the matcher; the rest tunes VICP
};

/// The lidar motion between scan `ref` and scan `ref + 1`.
struct ScanMatch {
  std::size_t ref = 0;
  double stamp_ref_s = 0.0;  ///< first beam of scan ref
  double stamp_cur_s = 0.0;  ///< first beam of scan ref + 1
  /// T_ref_cur between the two first-beam lidar frames; converged = false when it failed
  /// (`reason` says why).
  IcpResult match;
};

/// Matches every pair of consecutive scans. `scan_points` (kIcp): the points of each scan in its
/// lidar frame, e.g. de-skewed first, which removes the bias motion distortion puts into the
/// matches; empty: the scans as measured. Throws InputError when first-beam times do not increase.
std::vector<ScanMatch> matchConsecutiveScans(const Dataset& dataset,
                                             const ScanMotionParams& params = {},
                                             const std::vector<Points2>& scan_points = {});

/// Chains of T_world_lidar through the converged matches; a failed match ends one chain and the
/// next starts at its current scan. Chains of one pose are dropped.
struct MatchChains {
  std::vector<PoseSeries> chains;
  std::vector<std::vector<std::size_t>> scans;  ///< scans[c][i]: the scan of pose chains[c][i]
  int failed_matches = 0;
};
MatchChains chainMatches(const std::vector<ScanMatch>& matches);

/// Intervals from all chains (buildIntervals on each), concatenated.
IntervalSet buildIntervals(const Dataset& dataset, const std::vector<PoseSeries>& chains,
                           const IntervalParams& params);

/// One UMBmark run from a square-run dataset: start and end of the nominal odometry and of the
/// ground truth, and the encoder steps in between; clockwise when the true heading turned negative
/// overall. nullopt without truth.
std::optional<UmbmarkRun> umbmarkRunFromDataset(const Dataset& dataset);

}  // namespace slamprep::algo
