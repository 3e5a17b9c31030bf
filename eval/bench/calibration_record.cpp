#include "slamprep/eval/bench/calibration_record.hpp"

#include <cmath>
#include <numbers>
#include <utility>

#include "slamprep/core/odometry.hpp"
#include "slamprep/eval/bench/fault_score.hpp"
#include "slamprep/eval/bench/record_fields.hpp"
#include "slamprep/eval/metrics/calibration_error.hpp"
#include "slamprep/eval/metrics/consistency.hpp"
#include "slamprep/eval/metrics/odometry_drift.hpp"

namespace slamprep::eval {
namespace {

std::string key(CalibrationField field) {
  return keyOf(kCalibrationFieldKeys, field);
}

std::string key(CalibrationError kind) {
  return keyOf(kCalibrationErrorKeys, kind);
}

// calibrationError's parameter names: which parameter, and the scale to its key's unit.
const std::map<std::string, std::pair<CalibrationParam, double>>& metricParams() {
  static const std::map<std::string, std::pair<CalibrationParam, double>> kParams = {
      {"r_L", {CalibrationParam::kRL, 100.0}},
      {"r_R", {CalibrationParam::kRR, 100.0}},
      {"b", {CalibrationParam::kB, 100.0}},
      {"mount_x", {CalibrationParam::kMountX, 1.0}},
      {"mount_y", {CalibrationParam::kMountY, 1.0}},
      {"mount_yaw", {CalibrationParam::kMountYaw, 1.0}}};
  return kParams;
}

// Error and sigma per parameter, the NEES over the parameters the method estimates with its full
// covariance (SI units), and whether the truth lies within 3 sigma.
void scoreEstimate(const Dataset& dataset, const algo::CalibrationResult& result,
                   CalibrationRecord& r) {
  CalibrationEstimate estimate{result.geometry, std::nullopt, std::nullopt, std::nullopt};
  const Eigen::VectorXd sigma = result.sigma();
  if (sigma.size() >= 3) estimate.geometry_sigma = sigma.head<3>();
  if (result.estimates_mount) {
    estimate.T_base_lidar = result.T_base_lidar;
    if (sigma.size() >= 6) estimate.mount_sigma = sigma.segment<3>(3);
  }
  const auto error =
      calibrationError(estimate, *dataset.info.true_geometry, dataset.info.trueMount());
  Eigen::VectorXd error_si(static_cast<Eigen::Index>(error.parameters.size()));
  for (std::size_t i = 0; i < error.parameters.size(); ++i) {
    const auto& p = error.parameters[i];
    const auto& [param, scale] = metricParams().at(p.name);
    r.abs_error[param] = std::abs(p.error) * scale;
    r.signed_error[param] = p.error * scale;
    if (p.sigma) r.sigma[param] = *p.sigma * scale;
    error_si(i) = p.error * (p.unit == "relative" ? p.truth
                             : p.unit == "mm"     ? 1e-3
                                                  : std::numbers::pi / 180);
  }
  const auto k = error_si.size();
  if (result.covariance.rows() >= k && result.covariance.cols() >= k)
    r.nees = normalizedErrorSquared(error_si, result.covariance.topLeftCorner(k, k));
  r.inside_3sigma = error.all_within_3_sigma;
}

}  // namespace

const CalibrationParamValues& CalibrationRecord::operator[](CalibrationError kind) const {
  switch (kind) {
    case CalibrationError::kAbs:
      return abs_error;
    case CalibrationError::kSigned:
      return signed_error;
    case CalibrationError::kSigma:
      break;
  }
  return sigma;
}

CalibrationRecord calibrationRecord(const Dataset& dataset, const algo::CalibrationRun& run) {
  const algo::CalibrationResult& result = run.result;
  CalibrationRecord r;
  r.ok = result.ok;
  if (run.sideslip_s)
    r.sideslip = SideslipRecord{*run.sideslip_s * 1e3, run.sideslip_sigma_s * 1e3};
  if (!result.ok) {
    r.reason = result.reason;
    // With faults injected, a refusal counts as robust only when it names one of them.
    if (dataset.info.faults.is_object())
      r.refusal_names_fault = namesInjectedFault(result.reason, dataset);
    return r;
  }
  r.condition_number = result.condition_number;
  scoreEstimate(dataset, result, r);
  const PoseSeries odom =
      integrateEncoders(dataset.encoders, result.geometry, dataset.info.ticks_per_revolution);
  const DriftResult drift = odometryDrift(odom, dataset.groundtruth);
  if (drift.ok) r.drift_m = drift.final_position_error_m;
  r.odometry = odometryRecord(odom, dataset.groundtruth);
  return r;
}

void to_json(nlohmann::json& out, const CalibrationRecord& r) {
  out = {{key(CalibrationField::kOk), r.ok}};
  if (!r.ok) out[key(CalibrationField::kReason)] = r.reason;
  writeOptional(out, key(CalibrationField::kRefusalNamesFault), r.refusal_names_fault);
  writeOptional(out, key(CalibrationField::kConditionNumber), r.condition_number);
  for (const auto& [kind, name] : kCalibrationErrorKeys)
    if (!r[kind].empty()) out[std::string(name)] = r[kind];
  writeOptional(out, key(CalibrationField::kNees), r.nees);
  writeOptional(out, key(CalibrationField::kInside3Sigma), r.inside_3sigma);
  writeOptional(out, key(CalibrationField::kDrift), r.drift_m);
  out.update(nlohmann::json(r.odometry));
  if (r.sideslip)
    out[key(CalibrationField::kSideslip)] = {{"value", r.sideslip->value},
                                             {"sigma", r.sideslip->sigma}};
}

void from_json(const nlohmann::json& in, CalibrationRecord& r) {
  r.ok = readField<bool>(in, key(CalibrationField::kOk));
  r.reason = in.value(key(CalibrationField::kReason), std::string());
  r.refusal_names_fault = readOptional<bool>(in, key(CalibrationField::kRefusalNamesFault));
  r.condition_number = readOptional<double>(in, key(CalibrationField::kConditionNumber));
  r.abs_error = in.value(key(CalibrationError::kAbs), CalibrationParamValues{});
  r.signed_error = in.value(key(CalibrationError::kSigned), CalibrationParamValues{});
  r.sigma = in.value(key(CalibrationError::kSigma), CalibrationParamValues{});
  r.nees = readOptional<double>(in, key(CalibrationField::kNees));
  r.inside_3sigma = readOptional<bool>(in, key(CalibrationField::kInside3Sigma));
  r.drift_m = readOptional<double>(in, key(CalibrationField::kDrift));
  r.odometry = in.get<OdometryRecord>();
  r.sideslip.reset();
  if (in.contains(key(CalibrationField::kSideslip))) {
    const nlohmann::json& s = in.at(key(CalibrationField::kSideslip));
    r.sideslip = SideslipRecord{readField<double>(s, "value"), readField<double>(s, "sigma")};
  }
}

}  // namespace slamprep::eval
