#include "slamprep/eval/metrics/odometry_drift.hpp"

#include <cmath>
#include <numbers>

#include "slamprep/eval/metrics/trajectory_error.hpp"

namespace slamprep::eval {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

std::optional<double> ratio(double nominal, double calibrated) {
  if (!(calibrated > 0.0)) return std::nullopt;
  const double q = nominal / calibrated;
  return std::isfinite(q) ? std::optional<double>(q) : std::nullopt;
}

}  // namespace

DriftResult odometryDrift(const PoseSeries& T_odom_base, const PoseSeries& T_world_base_true,
                          const DriftParams& params) {
  DriftResult r;
  const AssociatedPoses a =
      associateByTime(T_odom_base, T_world_base_true, params.max_time_difference_s);
  r.unmatched = a.unmatched;
  if (a.estimate.empty()) {
    r.reason = "no odometry pose has ground truth within the time tolerance";
    return r;
  }
  r.T_world_odom = a.reference.front() * a.estimate.front().inverse();
  for (std::size_t i = 0; i < a.estimate.size(); ++i) {
    const SE2 E = a.reference[i].inverse() * (r.T_world_odom * a.estimate[i]);
    const double position_m = E.translation().norm();
    if (!std::isfinite(position_m) || !std::isfinite(E.yaw)) {
      r.reason = "pose " + std::to_string(i) + " is not finite";
      return r;
    }
    r.max_position_error_m = std::max(r.max_position_error_m, position_m);
    r.final_error = E;
    r.final_position_error_m = position_m;
    r.final_heading_error_deg = std::abs(E.yaw) * kDegPerRad;
    if (i > 0)
      r.path_length_m += (a.reference[i].translation() - a.reference[i - 1].translation()).norm();
  }
  r.matched = a.estimate.size();
  r.duration_s = a.stamps_s.back() - a.stamps_s.front();
  r.ok = true;
  return r;
}

DriftComparison compareDrift(const PoseSeries& nominal, const PoseSeries& calibrated,
                             const PoseSeries& T_world_base_true, const DriftParams& params) {
  DriftComparison c;
  c.nominal = odometryDrift(nominal, T_world_base_true, params);
  c.calibrated = odometryDrift(calibrated, T_world_base_true, params);
  if (!c.nominal.ok || !c.calibrated.ok) {
    c.reason =
        !c.nominal.ok ? "nominal: " + c.nominal.reason : "calibrated: " + c.calibrated.reason;
    return c;
  }
  c.final_position_ratio =
      ratio(c.nominal.final_position_error_m, c.calibrated.final_position_error_m);
  c.final_heading_ratio =
      ratio(c.nominal.final_heading_error_deg, c.calibrated.final_heading_error_deg);
  c.max_position_ratio = ratio(c.nominal.max_position_error_m, c.calibrated.max_position_error_m);
  c.ok = true;
  return c;
}

}  // namespace slamprep::eval
