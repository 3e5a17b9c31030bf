#include "slamprep/eval/bench/group_consistency.hpp"

#include <map>

#include "slamprep/eval/bench/trial_metrics.hpp"
#include "slamprep/eval/metrics/consistency.hpp"

namespace slamprep::eval {
namespace {

constexpr std::string_view kConsistency = "consistency";

using MethodRecords = std::map<std::string, std::vector<CalibrationRecord>>;

// Each method's records over the results, refusals left out.
MethodRecords estimatesByMethod(const std::vector<const nlohmann::json*>& results) {
  MethodRecords out;
  for (const auto* r : results)
    for (auto& [method, record] : calibrationRecords(*r)) {
      auto& records = out[method];  // a method that always refused still has its (empty) entry
      if (record.ok) records.push_back(std::move(record));
    }
  return out;
}

// The error statistics of one parameter over the records that reported its sigma.
void addParameter(const std::string& method, CalibrationParam param,
                  const std::vector<CalibrationRecord>& records, nlohmann::json& out) {
  std::vector<double> errors, sigmas;
  for (const CalibrationRecord& c : records)
    if (c.sigma[param] && c.signed_error[param]) {
      errors.push_back(*c.signed_error[param]);
      sigmas.push_back(*c.sigma[param]);
    }
  if (errors.empty()) return;
  const ErrorConsistency s = errorConsistency(errors, sigmas);
  const auto key = [&](ConsistencyStat stat) { return consistencyMetric(method, param, stat); };
  out[key(ConsistencyStat::kN)] = s.n;
  out[key(ConsistencyStat::kBias)] = s.bias;
  out[key(ConsistencyStat::kStd)] = s.std;
  out[key(ConsistencyStat::kRms)] = s.rms;
  out[key(ConsistencyStat::kCoverage1Sigma)] = s.coverage_1sigma;
  out[key(ConsistencyStat::kCoverage3Sigma)] = s.coverage_3sigma;
}

// The mean NEES over the records that have one.
void addNees(const std::string& method, const std::vector<CalibrationRecord>& records,
             nlohmann::json& out) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const CalibrationRecord& c : records)
    if (c.nees) sum += *c.nees, ++n;
  if (n == 0) return;
  out[consistencyMetric(method, NeesStat::kMean)] = sum / n;
  out[consistencyMetric(method, NeesStat::kN)] = n;
}

}  // namespace

std::string consistencyMetric(std::string_view method, CalibrationParam param,
                              ConsistencyStat stat) {
  return methodPrefix(TrialSection::kCalibration, method) + std::string(kConsistency) + "/" +
         std::string(nameOf(kCalibrationParamNames, param)) + "/" +
         std::string(nameOf(kConsistencyStatKeys, stat));
}

std::string consistencyMetric(std::string_view method, NeesStat stat) {
  return methodPrefix(TrialSection::kCalibration, method) + std::string(kConsistency) + "/" +
         std::string(nameOf(kNeesStatKeys, stat));
}

nlohmann::json consistencyOver(const std::vector<const nlohmann::json*>& results) {
  nlohmann::json out = nlohmann::json::object();
  for (const auto& [method, records] : estimatesByMethod(results)) {
    for (const CalibrationParam param : kCalibrationParams)
      addParameter(method, param, records, out);
    addNees(method, records, out);
  }
  return out;
}

}  // namespace slamprep::eval
