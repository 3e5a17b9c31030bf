#pragma once
// The lidar of a twin (docs/twin.md "Lidar"): what a recording's scans say of their sensor
// (rate, beams, angular layout, timing, range limits) and, against the world made from its map,
// how noisy its ranges are and where it returns nothing.

#include <string>
#include <vector>

#include "slamprep/core/dataset.hpp"
#include "slamprep/eval/bench/twin_walls.hpp"
#include "slamprep/eval/pipeline/match_trajectory.hpp"
#include "slamprep/sim/physics/planar_caster.hpp"

namespace slamprep::eval {

struct LidarLayout {
  std::size_t scans = 0;
  double rate_hz = 0.0;  ///< 1 / median stamp step
  double beams_per_scan_mean = 0.0;
  std::size_t beams_min = 0, beams_max = 0, beams_mode = 0;
  double angle_min_rad = 0.0;                   ///< of the most common layout
  double angle_increment_rad = 0.0;             ///< negative: clockwise
  double time_increment_s = 0.0;                ///< median; 0: instantaneous scans
  double range_min_m = 0.0, range_max_m = 0.0;  ///< the scans' limits (median)
  double usable_max_m = 0.0;                    ///< the longest valid reading
  double no_return_fraction = 0.0;              ///< invalid beams of all beams
  // The simulator's layout that reproduces it.
  int beams_per_revolution = 0;  ///< round(2 pi / |angle_increment|)
  double fov_rad = 0.0;          ///< min(2 pi, beams_mode |increment|)
  /// Added to the mount's yaw so the simulated beam i points where the recorded beam i did (the
  /// simulator starts at -fov/2 counter-clockwise, +fov/2 clockwise).
  double mount_yaw_shift_rad = 0.0;
};

LidarLayout fitLidarLayout(const Dataset& dataset);

struct LidarMapParams {
  double max_residual_m = 0.3;   ///< residuals beyond are outliers (clutter, people), not noise
  double angle_bin_deg = 10.0;   ///< no-return pattern by beam angle ...
  double range_bin_m = 0.5;      ///< ... and by the range the map predicts
  double lidar_height_m = 0.25;  ///< the plane the world is cast in
  /// Beams of consecutive scans whose predicted hits lie this close saw the same spot.
  double revisit_distance_m = 0.02;
  /// A range error fixed in the lidar's frame is fitted where the halves' per-beam means
  /// correlate beyond this (LidarAgainstMap::residual_beam_halves_correlation) and beyond 3 /
  /// sqrt(beams): neighbouring beams' means move together with the world's shape, so chance
  /// reaches 0.17 on 360 beams of a figure eight without any such error (seeds 1-8).
  double min_beam_halves_correlation = 0.25;
};

struct LidarAgainstMap {
  std::size_t beams = 0;           ///< beams of the scans compared
  std::size_t residuals = 0;       ///< measured and predicted within max_residual_m
  double range_noise_m = 0.0;      ///< 1.4826 MAD of measured - predicted range
  double residual_median_m = 0.0;  ///< signed median (a bias of the world's walls)
  /// Robust correlation of neighbouring beams' residuals (both within max_residual_m): range
  /// errors that move together along a wall tilt it, and a matcher takes a tilt for a turn.
  double residual_neighbour_correlation = 0.0;
  /// Robust correlation of the residuals of one spot of a wall seen by consecutive scans: range
  /// errors fixed in the world (the surfaces' own shape, clutter) are seen again, a lidar's own
  /// noise is drawn afresh; what a matcher sees as motion between two scans is the latter.
  double residual_revisit_correlation = 0.0;
  /// A range error fixed in the lidar's frame: each beam's mean residual over the first half of
  /// the scans against its mean over the second, correlated over the beams (a head that reads
  /// some beams long does so wherever it is; the world's shape, seen from changing places, does
  /// not repeat by beam). 0 where the scans' beam count varies or fewer than 30 beams have 10
  /// residuals in each half.
  double residual_beam_halves_correlation = 0.0;
  /// Each beam's mean residual less the mean over the beams, times sqrt(2 rho / (1 + rho)),
  /// the square root of a whole-recording mean's reliability (rho:
  /// residual_beam_halves_correlation), so that the pattern has the variance of the beams' own
  /// error; where rho is beyond chance (LidarMapParams::min_beam_halves_correlation), else
  /// empty: the twin's lidar.range_bias_by_beam_m.
  std::vector<double> range_bias_by_beam_m;
  /// Why a pattern beyond chance was not given (dropBeamBiasBeyondResidual); empty otherwise.
  std::string range_bias_not_given;
  double dropout_probability = 0.0;  ///< no return where the map predicts one within usable range
  double spurious_fraction = 0.0;    ///< a return where the map predicts none
  double escape_fraction = 0.0;      ///< beams for which the map predicts no wall (of all)
  double no_return_fraction = 0.0;   ///< no return within the usable range (of all)
  /// What the twin drops where its world has a wall: the no-returns its world's escapes do not
  /// already give, (no_return - escape) / (1 - escape), at least 0. Where the walls missed what
  /// the robot saw (spurious returns), dropout_probability would count those beams twice.
  double twin_dropout_probability = 0.0;
  std::vector<double> dropout_by_angle;         ///< per angle bin from -180 deg (lidar frame)
  std::vector<double> dropout_by_range;         ///< per predicted-range bin from 0
  std::vector<std::size_t> predicted_by_range;  ///< beams per range bin (the denominators)
  /// The pattern as the twin's factors on a beam's chance of a return
  /// (faults.dropped_beams.by_angle, by_range): keep(angle, range) = (1 -
  /// twin_dropout_probability) x angle factor x range factor, fitted to the returns of every
  /// (angle, range) bin with its drops scaled by twin_dropout_probability / dropout_probability;
  /// 1 for a bin without beams. By angle in the twin's lidar frame (the recording's beam angle
  /// minus mount_yaw_shift), so a blocked sector stays where the robot has it.
  std::vector<double> keep_factor_by_twin_angle;
  std::vector<double> keep_factor_by_range;
};

/// Casts every beam of the accepted scans (`use[k]`) in `world` from the matched trajectory
/// (the base at the scans' first beams, interpolated to every beam's time).
/// A range error fixed in the lidar's frame is a part of what the scans miss their map by: a
/// pattern whose RMS (over the beams it was fitted on) exceeds the recording's whole residual
/// (`residual_m`, the per-scan RMS residual's median) is the walls' own errors seen again by the
/// same beams of a robot that moved little, not the lidar's; it is dropped, and why is said.
void dropBeamBiasBeyondResidual(double residual_m, LidarAgainstMap& m);

LidarAgainstMap compareWithMap(const Dataset& dataset, const PoseSeries& T_world_base,
                               const std::vector<char>& use, const sim::PlanarCaster& world,
                               const LidarLayout& layout, const LidarMapParams& params = {});

/// The accepted scans' points in the matched trajectory's frame (the first scan is the map's
/// origin), nearer than `usable_max_m`; `accepted[k]` says which scans they came from.
std::vector<MapPoint> matchedMapPoints(const MatchTrajectory& run,
                                       const std::vector<Points2>& points, double usable_max_m,
                                       std::vector<char>& accepted);

/// The residuals' correlations of a dataset against its own map (ownMapCorrelations).
struct ResidualCorrelations {
  double neighbour = 0.0;  ///< LidarAgainstMap::residual_neighbour_correlation
  double revisit = 0.0;    ///< LidarAgainstMap::residual_revisit_correlation
  double transient = 0.0;  ///< transientReturns' fraction, on the same matched poses (or 0)
};

/// LidarAgainstMap's residual correlations of a dataset against its own map, and the share of
/// its returns no other moment supports (transient_returns.hpp): its scans
/// matched de-skewed (match --deskew vicp: a sweep matched as measured leaves its motion in the
/// residuals), the accepted scans' map made into walls (extractWalls), and every beam of those
/// scans cast in them from the matched poses. The same on a recording and on its twin: each
/// against the walls of its own matched map, so the twin's matched drift does not count.
/// `transient` is counted only with `count_transients` (the comparison's; the twin's tuning runs
/// do not read it).
ResidualCorrelations ownMapCorrelations(const Dataset& dataset, const LidarLayout& layout,
                                        const WallExtractionParams& walls = {},
                                        const LidarMapParams& params = {},
                                        bool count_transients = false);
/// The same on `vicp_points` (matchScanPoints(dataset, "vicp", false)) and their match
/// `vicp_run` (twinMatchOptions()), where the caller has them already.
ResidualCorrelations ownMapCorrelations(const Dataset& dataset, const ScanPoints& vicp_points,
                                        const MatchTrajectory& vicp_run, const LidarLayout& layout,
                                        const WallExtractionParams& walls = {},
                                        const LidarMapParams& params = {},
                                        bool count_transients = false);

/// What the twin tunes its range noise and its correlation to, measured alike on the recording
/// and the twin.
struct MatchedScans {
  /// Median of the accepted scans' point-to-line RMS residual, the scans matched as measured
  /// (slamprep match --deskew none).
  double residual_median_m = 0.0;
  /// ownMapCorrelations' neighbour: structure the walls do not have (clutter, curved surfaces)
  /// and range errors that move together, which a matcher reads as the pose.
  double neighbour_correlation = 0.0;
  double revisit_correlation = 0.0;  ///< ownMapCorrelations' revisit
};

MatchedScans measureMatchedScans(const Dataset& dataset, const LidarLayout& layout,
                                 const WallExtractionParams& walls = {},
                                 const LidarMapParams& params = {});
/// The same with ownMapCorrelations' vicp scans and match given (its second overload).
MatchedScans measureMatchedScans(const Dataset& dataset, const ScanPoints& vicp_points,
                                 const MatchTrajectory& vicp_run, const LidarLayout& layout,
                                 const WallExtractionParams& walls = {},
                                 const LidarMapParams& params = {});

}  // namespace slamprep::eval
