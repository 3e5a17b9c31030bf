#include "slamprep/eval/metrics/calibration_error.hpp"

#include <cmath>
#include <numbers>

namespace slamprep::eval {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// `scale` converts an SI difference into the report unit; `difference` is estimate - truth.
ParameterError makeError(const char* name, const char* unit, double estimate, double truth,
                         double difference, double scale, std::optional<double> sigma_si) {
  ParameterError e{name, unit, estimate, truth, difference * scale, std::nullopt, std::nullopt};
  if (sigma_si) {
    e.sigma = *sigma_si * std::abs(scale);
    e.within_3_sigma = std::abs(e.error) <= 3.0 * *e.sigma;
  }
  return e;
}

std::optional<double> component(const std::optional<Eigen::Vector3d>& v, int i) {
  return v ? std::optional<double>((*v)[i]) : std::nullopt;
}

bool validSigma(const std::optional<Eigen::Vector3d>& sigma) {
  return !sigma || (sigma->allFinite() && (sigma->array() >= 0.0).all());
}

std::string checkInputs(const CalibrationEstimate& est, const DiffDriveParams& truth) {
  const Eigen::Vector3d t(truth.radius_left_m, truth.radius_right_m, truth.wheel_base_m);
  const Eigen::Vector3d g(est.geometry.radius_left_m, est.geometry.radius_right_m,
                          est.geometry.wheel_base_m);
  if (!t.allFinite() || (t.array() <= 0.0).any()) return "true geometry must be finite and > 0";
  if (!g.allFinite()) return "estimated geometry is not finite";
  if (est.T_base_lidar && !est.T_base_lidar->vector().allFinite())
    return "estimated lidar mount is not finite";
  if (!validSigma(est.geometry_sigma) || !validSigma(est.mount_sigma))
    return "sigmas must be finite and >= 0";
  return "";
}

}  // namespace

CalibrationErrorResult calibrationError(const CalibrationEstimate& estimate,
                                        const DiffDriveParams& true_geometry,
                                        const std::optional<SE2>& true_T_base_lidar) {
  CalibrationErrorResult r;
  r.reason = checkInputs(estimate, true_geometry);
  if (!r.reason.empty()) return r;
  const DiffDriveParams& g = estimate.geometry;
  const DiffDriveParams& t = true_geometry;
  const auto& gs = estimate.geometry_sigma;
  r.parameters = {
      makeError("r_L", "relative", g.radius_left_m, t.radius_left_m,
                g.radius_left_m - t.radius_left_m, 1.0 / t.radius_left_m, component(gs, 0)),
      makeError("r_R", "relative", g.radius_right_m, t.radius_right_m,
                g.radius_right_m - t.radius_right_m, 1.0 / t.radius_right_m, component(gs, 1)),
      makeError("b", "relative", g.wheel_base_m, t.wheel_base_m, g.wheel_base_m - t.wheel_base_m,
                1.0 / t.wheel_base_m, component(gs, 2))};
  if (estimate.T_base_lidar && true_T_base_lidar) {
    const SE2& m = *estimate.T_base_lidar;
    const SE2& mt = *true_T_base_lidar;
    const auto& ms = estimate.mount_sigma;
    r.parameters.push_back(
        makeError("mount_x", "mm", m.x, mt.x, m.x - mt.x, 1e3, component(ms, 0)));
    r.parameters.push_back(
        makeError("mount_y", "mm", m.y, mt.y, m.y - mt.y, 1e3, component(ms, 1)));
    r.parameters.push_back(makeError("mount_yaw", "deg", m.yaw, mt.yaw,
                                     normalizeAngle(m.yaw - mt.yaw), kDegPerRad, component(ms, 2)));
  }
  for (const auto& p : r.parameters)
    if (p.within_3_sigma)
      r.all_within_3_sigma = r.all_within_3_sigma.value_or(true) && *p.within_3_sigma;
  r.ok = true;
  return r;
}

}  // namespace slamprep::eval
