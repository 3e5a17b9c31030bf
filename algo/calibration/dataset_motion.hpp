#pragma once
// Measured lidar motion from a dataset, as the calibration methods need it: from ground truth
// (an oracle run) or from scan matching consecutive scans.

#include <vector>

#include "algo/calibration/interval.hpp"
#include "algo/calibration/umbmark.hpp"
#include "algo/matching/icp.hpp"
#include "core/dataset.hpp"

namespace slamprep::algo {

/// T_world_lidar at every scan stamp from the true base poses and the dataset's mount.
/// Empty when the dataset has no ground truth.
PoseSeries lidarPosesFromGroundTruth(const Dataset& dataset);

/// Chains of T_world_lidar from point-to-line ICP between consecutive scans (guess from the
/// nominal odometry and the dataset's mount). A failed match ends one chain and starts the next.
struct IcpChains {
  std::vector<PoseSeries> chains;
  int failed_matches = 0;
};
IcpChains lidarPosesFromIcp(const Dataset& dataset, const IcpParams& params = {});
/// The same on given points per scan (scan_points[i]: scan i in its lidar frame at its stamp),
/// e.g. scans de-skewed first, which removes the bias motion distortion puts into the matches.
IcpChains lidarPosesFromIcp(const Dataset& dataset, const std::vector<Points2>& scan_points,
                            const IcpParams& params = {});

/// Intervals from all chains (buildIntervals on each), concatenated.
IntervalSet buildIntervals(const Dataset& dataset, const std::vector<PoseSeries>& chains,
                           const IntervalParams& params);

/// One UMBmark run from a square-run dataset: start and end of the nominal odometry and of the
/// ground truth; clockwise when the true heading turned negative overall. nullopt without truth.
std::optional<UmbmarkRun> umbmarkRunFromDataset(const Dataset& dataset);

}  // namespace slamprep::algo
