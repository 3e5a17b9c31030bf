#include "slamprep/algo/matching/keyframe_odometry.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <string>

namespace slamprep::algo {
namespace {

/// The newest keyframe and the submap its points went into.
struct KeyframeMap {
  LocalSubmap submap;
  SE2 T_world_kf;          ///< the newest keyframe's pose: the frame the reference is in
  std::size_t newest = 0;  ///< its scan index
  double travel_m = 0.0;   ///< distance between keyframes summed up to the newest

  void add(std::size_t scan, const SE2& T_world_scan, const Points2& points) {
    if (scan > 0) travel_m += between(T_world_kf, T_world_scan).translation().norm();
    T_world_kf = T_world_scan;
    newest = scan;
    submap.insert(points, T_world_scan, travel_m);
    submap.prune(T_world_scan.translation(), travel_m);
  }

  /// The submap in the newest keyframe's frame, prepared for point-to-line ICP.
  IcpReference reference(const IcpParams& icp) const {
    return IcpReference(submap.pointsIn(T_world_kf), icp, true);
  }
};

Points2 withinRange(const Points2& points, double max_range_m) {
  Points2 out;
  out.reserve(points.size());
  for (const auto& p : points)
    if (p.squaredNorm() <= max_range_m * max_range_m) out.push_back(p);
  return out;
}

bool beyond(const SE2& T, double distance_m, double angle_rad) {
  return T.translation().norm() > distance_m || std::abs(T.yaw) > angle_rad;
}

/// One guess of the scan's pose and what matching from it gave.
struct Hypothesis {
  GuessSource source;
  SE2 T_world_guess;
  IcpResult match;          ///< T_kf_scan from this guess
  SE2 T_world_pose;         ///< the pose it proposes: the match, fused with the odometry guess
  bool believable = false;  ///< converged, its pose within max_correction of its own guess
  ScanSupport support;      ///< of its pose (or of the guess, for a fallback)
};

bool near(const SE2& a, const SE2& b, double distance_m, double angle_rad) {
  return !beyond(between(a, b), distance_m, angle_rad);
}

/// The guesses for the pose of a scan after `T_world_prev`, in tie-break order, those within
/// the hypothesis separation of an earlier one left out.
std::vector<Hypothesis> guessesFor(const SE2& T_world_prev, const StepPrior& prior,
                                   const SE2& last_step, const KeyframeOdometryParams& params) {
  std::vector<std::pair<GuessSource, SE2>> steps;
  if (prior.odometry) steps.emplace_back(GuessSource::kOdometry, *prior.odometry);
  if (prior.gyro_yaw_rad) {
    const SE2 moved = prior.odometry.value_or(last_step);
    steps.emplace_back(GuessSource::kGyro, SE2(moved.x, moved.y, *prior.gyro_yaw_rad));
  }
  steps.emplace_back(GuessSource::kConstantVelocity, last_step);
  steps.emplace_back(GuessSource::kStill, SE2());
  std::vector<Hypothesis> out;
  for (const auto& [source, step] : steps) {
    const SE2 T_world_guess = T_world_prev * step;
    const bool seen = std::any_of(out.begin(), out.end(), [&](const Hypothesis& h) {
      return near(h.T_world_guess, T_world_guess, params.hypothesis_separation_m,
                  params.hypothesis_separation_rad);
    });
    if (!seen) out.push_back({source, T_world_guess, {}, T_world_guess, false, {}});
  }
  return out;
}

/// The match fused with the odometry guess, where the fused pose stays within the correction
/// limit of that guess (a stale or jumping odometry is not averaged in); else the match alone.
SE2 proposedPose(const IcpResult& match, const std::optional<SE2>& T_world_odometry,
                 const KeyframeMap& map, const KeyframeOdometryParams& params) {
  const SE2 T_world_match = map.T_world_kf * match.T_ref_cur;
  if (!T_world_odometry) return T_world_match;
  const SE2 T_world_fused =
      map.T_world_kf * fuseWithGuess(match.T_ref_cur, match.covariance,
                                     between(map.T_world_kf, *T_world_odometry),
                                     params.odometry_sigma_m, params.odometry_sigma_rad);
  return near(*T_world_odometry, T_world_fused, params.max_correction_m, params.max_correction_rad)
             ? T_world_fused
             : T_world_match;
}

void matchFrom(Hypothesis& h, const std::optional<SE2>& T_world_odometry, const KeyframeMap& map,
               const IcpReference& reference, const Points2& points,
               const KeyframeOdometryParams& params) {
  h.match =
      matchPointToLine(reference, points, between(map.T_world_kf, h.T_world_guess), params.icp);
  h.T_world_pose = proposedPose(h.match, T_world_odometry, map, params);
  h.believable = h.match.converged && near(h.T_world_guess, h.T_world_pose, params.max_correction_m,
                                           params.max_correction_rad);
  h.support = scanSupport(reference, points, between(map.T_world_kf, h.T_world_pose),
                          params.support_distance_m);
}

/// Of the believable matches, in guess order: a later one replaces the one kept so far only
/// where the map explains it clearly better (its Eq. 1 cost below 1 / preference_cost_ratio of
/// the kept one's). Along a corridor every guess's match costs the same, and the odometry's,
/// which knows how far the robot drove, stays. nullptr when none is believable.
const Hypothesis* bestMatch(const std::vector<Hypothesis>& hs, const KeyframeOdometryParams& p) {
  const Hypothesis* best = nullptr;
  for (const Hypothesis& h : hs)
    if (h.believable &&
        (!best || h.support.cost_m2 * p.preference_cost_ratio < best->support.cost_m2))
      best = &h;
  return best;
}

/// Where no match is accepted: the first guess (the odometry where there is one), unless the map
/// supports another guess's pose (min_support_fraction) clearly better; a scan the map explains
/// nowhere says nothing against the odometry.
const Hypothesis& bestGuess(std::vector<Hypothesis>& hs, const KeyframeMap& map,
                            const IcpReference& reference, const Points2& points,
                            const KeyframeOdometryParams& params) {
  if (hs.size() == 1) return hs.front();
  for (Hypothesis& h : hs)
    h.support = scanSupport(reference, points, between(map.T_world_kf, h.T_world_guess),
                            params.support_distance_m);
  const Hypothesis* best = &hs.front();
  for (const Hypothesis& h : hs)
    if (h.support.fraction() >= params.min_support_fraction &&
        h.support.cost_m2 * params.preference_cost_ratio < best->support.cost_m2)
      best = &h;
  return *best;
}

/// Why no match of the scan was accepted, for TrackedScan::match.reason and the counters.
void explainFallback(const std::vector<Hypothesis>& hs, const KeyframeOdometryParams& params,
                     TrackedScan& scan, KeyframeOdometry& out) {
  ++out.fallbacks;
  // No guess could have matched: the lidar saw too little (open space, a blocked head).
  if (scan.points < params.icp.min_inliers) {
    ++out.sparse;
    scan.match.reason = "only " + std::to_string(scan.points) + " points within max_range (need " +
                        std::to_string(params.icp.min_inliers) + "): the lidar saw too little";
    return;
  }
  const bool converged =
      std::any_of(hs.begin(), hs.end(), [](const Hypothesis& h) { return h.match.converged; });
  const bool believable =
      std::any_of(hs.begin(), hs.end(), [](const Hypothesis& h) { return h.believable; });
  if (believable) {
    ++out.unsupported;
    scan.match.reason = "converged, but under " +
                        std::to_string(int(100 * params.min_support_fraction)) +
                        " % of the scan lies on the map: not supported";
  } else if (converged) {
    ++out.rejected;
    scan.match.reason = "converged beyond max_correction from the guess: not believed";
  }
}

/// Tracks scan k: its guesses, a match from each, the best supported, or a fallback.
TrackedScan trackScan(const Points2& points, const StepPrior& prior, const SE2& T_world_prev,
                      const SE2& last_step, const KeyframeMap& map, const IcpReference& reference,
                      const KeyframeOdometryParams& params, KeyframeOdometry& out) {
  const std::optional<SE2> T_world_odometry =
      prior.odometry ? std::optional<SE2>(T_world_prev * *prior.odometry) : std::nullopt;
  std::vector<Hypothesis> hs = guessesFor(T_world_prev, prior, last_step, params);
  for (Hypothesis& h : hs) matchFrom(h, T_world_odometry, map, reference, points, params);
  TrackedScan scan;
  scan.keyframe = map.newest;
  scan.map_points = reference.points().size();
  scan.points = points.size();
  scan.hypotheses = hs.size();
  if (hs.size() > 1) ++out.multi_hypothesis;
  const Hypothesis* best = bestMatch(hs, params);
  if (best && best->support.fraction() >= params.min_support_fraction) {
    scan.T_world_lidar = best->T_world_pose;
    scan.match = best->match;
    scan.guess = best->source;
    scan.support = best->support;
    ++out.matched;
  } else {
    scan.match = best ? best->match : hs.front().match;
    const Hypothesis& fallback = bestGuess(hs, map, reference, points, params);
    scan.T_world_lidar = fallback.T_world_guess;
    scan.guess = fallback.source;
    scan.support = fallback.support;
    scan.fallback = true;
    explainFallback(hs, params, scan, out);
  }
  ++out.won_by[static_cast<std::size_t>(scan.guess)];
  return scan;
}

}  // namespace

std::string sparseScansCause(std::size_t sparse, std::size_t attempted) {
  if (sparse == 0 || 2 * sparse < attempted) return "";
  return std::to_string(sparse) + " of " + std::to_string(attempted) +
         " scans hold fewer points than ICP needs: the lidar saw little";
}

std::string_view guessSourceName(GuessSource source) {
  return nameOf(kGuessSourceNames, source);
}

SE2 fuseWithGuess(const SE2& T_kf_match, const Eigen::Matrix3d& match_covariance,
                  const SE2& T_kf_guess, double odometry_sigma_m, double odometry_sigma_rad) {
  if (odometry_sigma_m <= 0.0 || odometry_sigma_rad <= 0.0) return T_kf_match;
  const Eigen::Vector3d d(T_kf_match.x - T_kf_guess.x, T_kf_match.y - T_kf_guess.y,
                          normalizeAngle(T_kf_match.yaw - T_kf_guess.yaw));
  const Eigen::Matrix3d info_match = match_covariance.inverse();
  const Eigen::Vector3d info_odo(1.0 / (odometry_sigma_m * odometry_sigma_m),
                                 1.0 / (odometry_sigma_m * odometry_sigma_m),
                                 1.0 / (odometry_sigma_rad * odometry_sigma_rad));
  const Eigen::Matrix3d info = info_match + Eigen::Matrix3d(info_odo.asDiagonal());
  const Eigen::Vector3d step = info.ldlt().solve(info_match * d);
  return SE2(T_kf_guess.x + step.x(), T_kf_guess.y + step.y(),
             normalizeAngle(T_kf_guess.yaw + step.z()));
}

KeyframeOdometry trackKeyframes(const std::vector<Points2>& all_points,
                                const std::vector<StepPrior>& priors,
                                const KeyframeOdometryParams& params,
                                const SE2& T_world_lidar_start) {
  assert(priors.size() == all_points.size());
  std::vector<Points2> points;
  points.reserve(all_points.size());
  for (const Points2& p : all_points) points.push_back(withinRange(p, params.max_range_m));
  KeyframeOdometry out;
  if (points.empty()) return out;
  KeyframeMap map{LocalSubmap(params.submap), T_world_lidar_start};
  map.add(0, T_world_lidar_start, points[0]);
  IcpReference reference = map.reference(params.icp);
  TrackedScan first;
  first.T_world_lidar = T_world_lidar_start;
  first.is_keyframe = true;
  first.map_points = reference.points().size();
  first.points = points[0].size();
  out.scans.push_back(std::move(first));
  out.keyframes = 1;
  SE2 last_step;  // the last step taken: the constant-velocity guess
  for (std::size_t k = 1; k < points.size(); ++k) {
    const SE2 T_world_prev = out.scans.back().T_world_lidar;
    TrackedScan scan =
        trackScan(points[k], priors[k], T_world_prev, last_step, map, reference, params, out);
    last_step = between(T_world_prev, scan.T_world_lidar);
    // A new keyframe once the scan has left the current one, matched or not: a map the robot has
    // left would make every later match fail.
    if (beyond(between(map.T_world_kf, scan.T_world_lidar), params.keyframe_distance_m,
               params.keyframe_angle_rad)) {
      map.add(k, scan.T_world_lidar, points[k]);
      reference = map.reference(params.icp);
      scan.is_keyframe = true;
      ++out.keyframes;
    }
    out.scans.push_back(std::move(scan));
  }
  return out;
}

KeyframeOdometry trackKeyframes(const std::vector<Points2>& points,
                                const std::vector<std::optional<SE2>>& increments,
                                const KeyframeOdometryParams& params,
                                const SE2& T_world_lidar_start) {
  std::vector<StepPrior> priors(increments.size());
  for (std::size_t k = 0; k < increments.size(); ++k) priors[k].odometry = increments[k];
  return trackKeyframes(points, priors, params, T_world_lidar_start);
}

}  // namespace slamprep::algo
