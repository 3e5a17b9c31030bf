#pragma once
// Lidar odometry by scan-to-local-map matching (docs/matching.md): each scan is matched
// (point-to-line ICP) against a local submap (algo/matching/local_submap.hpp: the voxel-
// downsampled points of the keyframes of the last metres of travel), expressed in the newest
// keyframe's frame; the guess is the previous pose composed with the odometry increment. A scan
// becomes a keyframe, and its points enter the submap, once it has moved far enough from the
// current one. Matching a map that stays put while the robot moves within it adds no drift, where
// chaining scan-to-scan matches adds the error of every pair.
//
// Guesses (docs/matching.md "Hypotheses"): the odometry's step, the gyro's turn (the odometry's
// or the last step's translation with the yaw the gyro measured), the last accepted step
// (constant velocity) and standing still. Where they disagree by more than the ICP's basin, the
// scan is matched from each and the result the map explains best (scan_support.hpp, Eq. 1)
// wins; a later guess of that list must be clearly better to replace an earlier one. A match is
// accepted because the scan supports it (converged, and at least min_support_fraction of its points
// lie on the map), never because it agrees with a guess: a stale odometry that jumps 85 degrees in
// one step is one guess among four, not the answer the match must confirm.
//
// Failed matches: the scan's pose is the first guess (the odometry step), or another guess whose
// pose the map supports clearly better; counted as a fallback.

#include <array>
#include <cstddef>
#include <numbers>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/algo/matching/icp.hpp"
#include "slamprep/algo/matching/local_submap.hpp"
#include "slamprep/algo/matching/scan_support.hpp"
#include "slamprep/core/enum_names.hpp"
#include "slamprep/core/laser_scan.hpp"
#include "slamprep/core/se2.hpp"

namespace slamprep::algo {

struct KeyframeOdometryParams {
  /// The matcher. Defaults tuned on the benchmark logs (docs/matching.md "Defaults").
  IcpParams icp = defaultIcp();
  /// A scan farther than this from the current keyframe (translation) becomes a keyframe ...
  double keyframe_distance_m = 0.3;
  /// ... or turned more than this.
  double keyframe_angle_rad = 10.0 * std::numbers::pi / 180.0;
  /// The local map: every keyframe's points, voxel-downsampled, forgotten by distance and travel.
  LocalSubmapParams submap;
  /// Points farther than this from the sensor are left out: some logs write "no return" as a
  /// reading at the sensor's range limit (ACES: 50 m), which would be a phantom wall.
  double max_range_m = 40.0;
  /// Odometry noise per scan step (1 sigma). An accepted match is fused with the odometry
  /// guess by information (below): where the scan constrains the pose poorly (a corridor's
  /// length), the odometry decides. 0: the match alone.
  double odometry_sigma_m = 0.01;
  double odometry_sigma_rad = 0.3 * std::numbers::pi / 180.0;
  /// A match that ends farther than this from the guess it started at has left the ICP's basin
  /// (a wrong local minimum): that hypothesis is not believed. The odometry guess is fused with
  /// the result only where it lies within this of it.
  double max_correction_m = 0.5;
  double max_correction_rad = 20.0 * std::numbers::pi / 180.0;
  /// Guesses farther apart than this (translation or rotation) are matched each: closer ones
  /// start in the same basin of the ICP and end in the same minimum.
  double hypothesis_separation_m = 0.1;
  double hypothesis_separation_rad = 3.0 * std::numbers::pi / 180.0;
  /// Scan support (scan_support.hpp): a point within this of the map explains the scan there ...
  double support_distance_m = 0.1;
  /// ... and a converged match is accepted when at least this fraction of the points the map
  /// overlaps does (0.1: the lowest accepted match of the three tuning logs, ACES, had 0.15 and
  /// was right; a scan that fits nowhere has far less).
  double min_support_fraction = 0.1;
  /// A later guess's match (or pose) replaces an earlier one's only where its Eq. 1 cost is below
  /// 1 / this of the earlier's: where the scan cannot tell them apart (a corridor's length), the
  /// earlier guess (the odometry) decides.
  /// 3: at 1.5 and 2 fr079 took four constant-velocity matches whose cost was 2-4x lower, each
  /// as right locally as the odometry's (relations within 0.3 deg), and its drift later ran
  /// 30 degrees off; 3 and 5 gave the same results on all three tuning logs.
  double preference_cost_ratio = 3.0;

  static IcpParams defaultIcp() {
    IcpParams p;
    p.max_iterations = 100;
    p.max_correspondence_distance_m = 0.5;
    p.trim_fraction = 0.0;
    // Chosen on the real benchmark logs (results/real/README.md): 4 to 8 all meet Intel's row.
    p.outlier_sigmas = 6.0;
    // Every point from the first round: a 180-beam scan's every 4th point leaves too few pairs.
    p.coarse_stride = 1;
    // The submap's walls, seen from several keyframes, are thicker than one scan's.
    p.line_max_thickness = 0.5;
    // Converged at 0.5 mm / 0.1 mrad steps: 1 degree beams at 5-10 m resolve no finer, and
    // tighter steps end in the slow limit cycles of nearest-neighbour correspondences.
    p.translation_tolerance_m = 5e-4;
    p.rotation_tolerance_rad = 1e-4;
    return p;
  }
};

/// Where a guess of the motion between two scans came from, in the order near-ties are broken.
enum class GuessSource { kOdometry, kGyro, kConstantVelocity, kStill };
/// As the match JSON and the summary write them ("guess", "won_by"), in the order above.
inline constexpr auto kGuessSourceNames = std::to_array<EnumName<GuessSource>>({
    {GuessSource::kOdometry, "odometry"},
    {GuessSource::kGyro, "gyro"},
    {GuessSource::kConstantVelocity, "constant_velocity"},
    {GuessSource::kStill, "still"},
});
inline constexpr std::size_t kGuessSources = kGuessSourceNames.size();
std::string_view guessSourceName(GuessSource source);

/// What the log says of the motion from scan k-1 to scan k (lidar frame, first beams).
struct StepPrior {
  std::optional<SE2> odometry;         ///< T_prev_cur from the odometry
  std::optional<double> gyro_yaw_rad;  ///< the yaw the gyro turned between the two scans
};

/// What happened to one scan.
struct TrackedScan {
  SE2 T_world_lidar;           ///< pose of the scan's (first-beam) lidar frame
  std::size_t keyframe = 0;    ///< index of the keyframe whose frame the match is in
  IcpResult match;             ///< T_ref_cur = T_keyframe_scan; converged = false when it failed
  bool fallback = false;       ///< pose taken from the guess (failed or rejected match)
  bool is_keyframe = false;    ///< this scan started a keyframe
  std::size_t map_points = 0;  ///< points of the local map it was matched against
  std::size_t points = 0;      ///< points of the scan within max_range_m
  GuessSource guess = GuessSource::kOdometry;  ///< the guess whose match (or pose) was taken
  std::size_t hypotheses = 1;                  ///< distinct guesses matched
  ScanSupport support;                         ///< of the pose taken
};

struct KeyframeOdometry {
  std::vector<TrackedScan> scans;  ///< one per input scan; scan 0 is the first keyframe
  std::size_t matched = 0;         ///< scans 1..n-1 whose match was accepted
  std::size_t fallbacks = 0;       ///< scans 1..n-1 placed by the guess instead
  std::size_t rejected = 0;        ///< of the fallbacks: converged, but beyond max_correction
  std::size_t keyframes = 0;
  std::size_t unsupported = 0;  ///< of the fallbacks: converged, but the map did not support it
  std::size_t sparse = 0;       ///< of the fallbacks: fewer points than icp.min_inliers
  std::size_t multi_hypothesis = 0;  ///< scans whose guesses disagreed, so each was matched
  /// Scans 1..n-1 per GuessSource whose guess won (matched or fallen back to).
  std::array<std::size_t, kGuessSources> won_by{};
};

/// Where at least half of the `attempted` scans held fewer points than ICP needs
/// (KeyframeOdometry::sparse), the cause of failed matches in words; else empty.
std::string sparseScansCause(std::size_t sparse, std::size_t attempted);

/// The information-weighted mean of the match and the guess, both T_kf_scan, as (x, y, yaw)
/// vectors: g + (C_match^-1 + C_odo^-1)^-1 C_match^-1 (m - g), C_odo = diag(s_m^2, s_m^2, s_rad^2)
/// (one Gauss-Newton step of both priors; corrections are small, so the vector form is exact
/// enough).
SE2 fuseWithGuess(const SE2& T_kf_match, const Eigen::Matrix3d& match_covariance,
                  const SE2& T_kf_guess, double odometry_sigma_m, double odometry_sigma_rad);

/// Tracks `points` (each scan in its own lidar frame, in time order). `priors[k]` is what the log
/// says of the motion from scan k-1 to scan k (index 0 unused). The first scan sits at
/// `T_world_lidar_start`.
KeyframeOdometry trackKeyframes(const std::vector<Points2>& points,
                                const std::vector<StepPrior>& priors,
                                const KeyframeOdometryParams& params = {},
                                const SE2& T_world_lidar_start = SE2());

/// The same with odometry steps only (nullopt: no odometry for that step).
KeyframeOdometry trackKeyframes(const std::vector<Points2>& points,
                                const std::vector<std::optional<SE2>>& increments,
                                const KeyframeOdometryParams& params = {},
                                const SE2& T_world_lidar_start = SE2());

}  // namespace slamprep::algo
