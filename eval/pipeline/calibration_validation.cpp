#include "slamprep/eval/pipeline/calibration_validation.hpp"

#include <cmath>
#include <numbers>
#include <utility>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/pipeline/match_trajectory.hpp"

namespace slamprep::eval {
namespace {

// (start, end) index pairs of the windows (see heldOutError).
std::vector<std::pair<std::size_t, std::size_t>> windowPairs(const std::vector<double>& t,
                                                             double window_s) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  if (t.size() < 2) return pairs;
  std::size_t j = 0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double target = t[i] + window_s;
    if (target > t.back()) break;  // the window would run past the part's end
    j = std::max(j, i + 1);
    while (j + 1 < t.size() && std::abs(t[j + 1] - target) <= std::abs(t[j] - target)) ++j;
    pairs.emplace_back(i, j);
  }
  if (pairs.empty()) pairs.emplace_back(0, t.size() - 1);  // shorter than one window
  return pairs;
}

}  // namespace

ValidationSplit splitForValidation(const Dataset& d, double fraction, const std::string& source) {
  if (!(fraction > 0.0 && fraction < 1.0))
    throw InputError("--validate-fraction", "must be between 0 and 1 (exclusive)");
  ValidationSplit split;
  if (d.scans.size() >= 2) {
    const double t0 = d.scans.front().scan.stamp_s, t1 = d.scans.back().scan.stamp_s;
    split.t_split_s = t0 + (1.0 - fraction) * (t1 - t0);
  }
  split.calibration = d;
  split.held_out = d;
  split.calibration.scans.clear();
  split.held_out.scans.clear();
  for (const ScanRecord& record : d.scans)
    (record.scan.stamp_s < split.t_split_s ? split.calibration : split.held_out)
        .scans.push_back(record);
  if (split.calibration.scans.size() < 3 || split.held_out.scans.size() < 3)
    throw InputError(source, "--validate-fraction " + std::to_string(fraction) + " leaves " +
                                 std::to_string(split.calibration.scans.size()) + " scans to " +
                                 "calibrate on and " + std::to_string(split.held_out.scans.size()) +
                                 " held out: each part needs 3 or more");
  return split;
}

HeldOutPart heldOutPart(const Dataset& held_out, const OdometryEncoders& odometry,
                        const HeldOutParams& params) {
  HeldOutPart part{{}, {}, odometry, params, held_out.scans.size()};
  const bool instantaneous =
      !held_out.scans.empty() && held_out.scans.front().scan.time_increment_s == 0.0;
  MatchTrajectoryOptions options;
  options.stamp_is_last_beam = params.stamp_is_last_beam;
  // The match alone, not fused with the nominal odometry: the reference must not lean towards
  // the raw geometry it is to judge.
  options.params.odometry_sigma_m = 0.0;
  options.params.odometry_sigma_rad = 0.0;
  const ScanPoints points =
      matchScanPoints(held_out, instantaneous ? "none" : "vicp", params.stamp_is_last_beam);
  const MatchTrajectory run = matchTrajectory(held_out, points, options);
  for (std::size_t k = 0; k < run.tracked.scans.size(); ++k) {
    if (run.tracked.scans[k].fallback) continue;
    part.stamps_s.push_back(run.pose_time_s[k]);
    part.T_world_lidar.push_back(run.tracked.scans[k].T_world_lidar);
  }
  return part;
}

algo::HeldOutError heldOutError(const HeldOutPart& part, const DiffDriveParams& geometry,
                                const SE2& T_base_lidar) {
  const PoseSeries odometry = integrateOdometry(part.odometry, geometry);
  std::vector<double> stamps;
  std::vector<SE2> matched, integrated;  // Q and P at the scans the odometry covers
  for (std::size_t k = 0; k < part.stamps_s.size(); ++k) {
    const auto T_odom_base = odometry.at(part.stamps_s[k]);
    if (!T_odom_base) continue;
    stamps.push_back(part.stamps_s[k]);
    matched.push_back(part.T_world_lidar[k]);
    integrated.push_back(*T_odom_base * T_base_lidar);
  }
  const auto pairs = windowPairs(stamps, part.params.window_s);
  if (pairs.empty())
    throw InputError(part.odometry.source,
                     "held-out part: fewer than 2 matched scans with odometry");
  algo::HeldOutError error;
  for (const auto& [i, j] : pairs) {
    const SE2 E = between(matched[i], matched[j]).inverse() * between(integrated[i], integrated[j]);
    error.trans_m += std::hypot(E.x, E.y);
    error.rot_deg += std::abs(E.yaw) * 180.0 / std::numbers::pi;
  }
  error.trans_m /= static_cast<double>(pairs.size());
  error.rot_deg /= static_cast<double>(pairs.size());
  return error;
}

algo::ValidationFigures validationFigures(const HeldOutPart& part, const algo::HeldOutError& raw,
                                          const algo::CalibrationRun& run, const SE2& dataset_mount,
                                          double fraction) {
  const algo::CalibrationResult& r = run.result;
  algo::ValidationFigures v{
      fraction, raw,
      heldOutError(part, r.geometry, r.estimates_mount ? r.T_base_lidar : dataset_mount),
      std::nullopt};
  if (r.estimates_mount) v.calibrated_wheels = heldOutError(part, r.geometry, dataset_mount);
  return v;
}

}  // namespace slamprep::eval
