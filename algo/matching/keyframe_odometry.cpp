#include "algo/matching/keyframe_odometry.hpp"

#include <Eigen/Dense>
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

}  // namespace

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
                                const std::vector<std::optional<SE2>>& increments,
                                const KeyframeOdometryParams& params,
                                const SE2& T_world_lidar_start) {
  assert(increments.size() == all_points.size());
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
  out.scans.push_back(std::move(first));
  out.keyframes = 1;
  SE2 last_step;  // the last accepted motion: the guess where there is no odometry
  for (std::size_t k = 1; k < points.size(); ++k) {
    const SE2 T_world_prev = out.scans.back().T_world_lidar;
    const SE2 T_world_guess = T_world_prev * increments[k].value_or(last_step);
    const SE2 T_world_kf = map.T_world_kf;  // a copy: add() moves it
    TrackedScan scan;
    scan.T_world_lidar = T_world_guess;
    scan.keyframe = map.newest;
    scan.fallback = true;
    scan.map_points = reference.points().size();
    const SE2 T_kf_guess = between(T_world_kf, T_world_guess);
    scan.match = matchPointToLine(reference, points[k], T_kf_guess, params.icp);
    SE2 T_kf_scan = scan.match.T_ref_cur;
    if (increments[k])  // only an odometry guess carries information of its own
      T_kf_scan = fuseWithGuess(T_kf_scan, scan.match.covariance, T_kf_guess,
                                params.odometry_sigma_m, params.odometry_sigma_rad);
    const SE2 T_world_match = T_world_kf * T_kf_scan;
    const bool believable = !beyond(between(T_world_guess, T_world_match), params.max_correction_m,
                                    params.max_correction_rad);
    if (scan.match.converged && believable) {
      scan.T_world_lidar = T_world_match;
      scan.fallback = false;
      ++out.matched;
    } else {
      ++out.fallbacks;
      if (scan.match.converged) {
        ++out.rejected;
        scan.match.reason = "converged beyond max_correction from the guess: not believed";
      }
    }
    last_step = between(T_world_prev, scan.T_world_lidar);
    // A new keyframe once the scan has left the current one, matched or not: a map the robot has
    // left would make every later match fail.
    if (beyond(between(T_world_kf, scan.T_world_lidar), params.keyframe_distance_m,
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

}  // namespace slamprep::algo
