#include "slamprep/eval/bench/group_consistency.hpp"

#include <map>
#include <optional>

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
std::optional<ErrorConsistency> parameterConsistency(
    CalibrationParam param, const std::vector<CalibrationRecord>& records) {
  std::vector<double> errors, sigmas;
  for (const CalibrationRecord& c : records)
    if (c.sigma[param] && c.signed_error[param]) {
      errors.push_back(*c.signed_error[param]);
      sigmas.push_back(*c.sigma[param]);
    }
  if (errors.empty()) return std::nullopt;
  return errorConsistency(errors, sigmas);
}

// The mean NEES over the records that have one.
std::optional<NeesConsistency> neesConsistency(const std::vector<CalibrationRecord>& records) {
  double sum = 0.0;
  std::size_t n = 0;
  for (const CalibrationRecord& c : records)
    if (c.nees) sum += *c.nees, ++n;
  if (n == 0) return std::nullopt;
  return NeesConsistency{sum / n, n};
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

GroupConsistency consistencyOver(const std::vector<const nlohmann::json*>& results) {
  GroupConsistency out;
  for (const auto& [method, records] : estimatesByMethod(results)) {
    MethodConsistency m;
    for (const CalibrationParam param : kCalibrationParams)
      if (auto e = parameterConsistency(param, records)) m.params[param] = *e;
    m.nees = neesConsistency(records);
    if (!m.params.empty() || m.nees) out[method] = std::move(m);
  }
  return out;
}

}  // namespace slamprep::eval
