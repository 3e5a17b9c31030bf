#pragma once
// Loop closures for a chain of scan-to-scan matches. Where the chain comes back to a place it
// passed at least `min_gap_s` earlier, the two scans are matched directly; the difference between
// that heading and the chained one is the heading the matches accumulated in between. A linear
// least-squares heading graph spreads it back over the chain (docs/calibration.md, "Loop
// closures"). Only headings change: each link keeps its matched translation, in its own frame.
//
// Why headings: a calibration reads r_R - r_L from the heading change over straight driving, so a
// heading drift of the matches becomes a wheel-radius difference that no residual of the same
// log can reveal (30 simulated seeds: the r_R - r_L error was 2.2 reported sigmas wide).

#include <Eigen/Sparse>
#include <cstddef>
#include <utility>
#include <vector>

#include "slamprep/algo/matching/icp.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep::algo {

struct LoopClosureParams {
  /// A pair of poses closer in time than this is no loop: short loops (an in-place spin) carry
  /// little drift and would only tie neighbouring links together.
  double min_gap_s = 10.0;
  /// At most one candidate scan per this much time, so a long log costs a few matches per second.
  double keyframe_spacing_s = 1.0;
  /// Chained lidar positions this close ...
  double max_distance_m = 0.3;
  /// ... and headings this close (20 deg) make a candidate pair: their scans overlap.
  double max_yaw_rad = 0.35;
  /// A direct match whose heading disagrees with the chain by more than this (2 deg) is taken
  /// for a false loop (a look-alike place) or a failed match and refused.
  double max_disagreement_rad = 0.035;
  /// The matcher for the direct matches (point-to-line, as the chain's).
  IcpParams icp;
};

/// One direct match used as a loop closure.
struct LoopClosure {
  std::size_t from = 0;  ///< chain index of the earlier pose
  std::size_t to = 0;    ///< chain index of the later pose
  /// Direct heading from `from` to `to` minus the chained one: what the links in between
  /// accumulated, with the opposite sign.
  double heading_correction_rad = 0.0;
};

struct LoopCorrection {
  PoseSeries T_world_lidar;          ///< the chain with its heading drift spread back
  std::vector<LoopClosure> loops;    ///< direct matches used, in time order of `to`
  int candidates = 0;                ///< pairs matched directly
  int refused = 0;                   ///< of those: did not converge, or disagreed too much
  double max_link_change_rad = 0.0;  ///< largest heading change of one link
};

/// Closes the loops of one chain. `points[i]` are the scan points (lidar frame) of chain pose i;
/// pose i's frame is the lidar at that scan's first beam, as in the chain.
LoopCorrection closeLoops(const PoseSeries& T_world_lidar,
                          const std::vector<const Points2*>& points,
                          const LoopClosureParams& params = {});

/// Normal matrix of the heading graph over poses 1..poses-1 (pose 0 held): every link (i, i+1)
/// and every loop (from, to) adds its incidence, each weighing one. Shared with the covariance
/// that propagates a correction (algo/calibration/loop_covariance.hpp).
Eigen::SparseMatrix<double> headingGraphMatrix(
    std::size_t poses, const std::vector<std::pair<std::size_t, std::size_t>>& loops);

/// The heading graph alone (Eq. in docs/calibration.md): corrections delta_i, delta_0 = 0, that
/// minimise sum_i (delta_{i+1} - delta_i)^2 + sum_loops (delta_to - delta_from - c)^2, each link
/// and each direct match weighing the same (both are one scan match). Returns one per pose.
std::vector<double> headingCorrections(std::size_t poses, const std::vector<LoopClosure>& loops);

}  // namespace slamprep::algo
