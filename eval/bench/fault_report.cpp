#include "slamprep/eval/bench/fault_report.hpp"

#include <cstdio>
#include <set>
#include <sstream>

#include "slamprep/eval/bench/trial_metrics.hpp"

namespace slamprep::eval {
namespace {

// The sweep key a faults suite's groups differ in.
constexpr const char* kFaultsEnable = "faults.enable";

// "mean ± std" of a group metric (scaled), or "-" when no trial has it.
std::string stat(const SummaryMetrics& metrics, const std::string& path, double scale = 1.0) {
  const auto it = metrics.find(path);
  if (it == metrics.end()) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g ± %.2g", scale * it->second.mean, scale * it->second.std);
  return buf;
}

std::string rate(const SummaryMetrics& metrics, const std::string& path) {
  const auto it = metrics.find(path);
  if (it == metrics.end()) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f %%", 100.0 * it->second.mean);
  return buf;
}

// Methods present in any group under "calibration/<method>/" or "deskew/<method>/".
std::set<std::string> methods(const std::vector<SummaryGroup>& groups, TrialSection section) {
  std::set<std::string> out;
  for (const auto& g : groups)
    for (const auto& [path, v] : g.metrics)
      if (std::string method = methodOfMetric(section, path); !method.empty())
        out.insert(std::move(method));
  return out;
}

}  // namespace

std::string faultRobustnessSection(const SuiteSummary& summary) {
  const std::vector<SummaryGroup>& groups = summary.groups;
  if (groups.empty()) return "";
  for (const auto& g : groups)
    if (!g.sweep.contains(kFaultsEnable)) return "";
  std::ostringstream out;
  out << "## Robustness against faults\n\nPer condition (`faults.enable`, docs/faults.md), mean "
         "± standard deviation over the seeds. Errors are absolute, in % of the true value; "
         "`ok` counts trials where the method gave an estimate; `refused, naming the fault` "
         "counts refusals whose reason names a fault that was on.\n\n";
  for (const std::string& m : methods(groups, TrialSection::kCalibration)) {
    const auto abs = [&](CalibrationParam p) {
      return calibrationMetric(m, CalibrationError::kAbs, p);
    };
    out << "### Calibration: " << m << "\n\n| condition | ok | r_L err [%] | r_R err [%] | "
        << "b err [%] | truth in 3σ | refused, naming the fault |\n| :-- | --: | --: | --: | "
        << "--: | --: | --: |\n";
    for (const auto& g : groups) {
      const SummaryMetrics& x = g.metrics;
      out << "| " << g.sweep.at(kFaultsEnable) << " | "
          << rate(x, calibrationMetric(m, CalibrationField::kOk)) << " | "
          << stat(x, abs(CalibrationParam::kRL)) << " | " << stat(x, abs(CalibrationParam::kRR))
          << " | " << stat(x, abs(CalibrationParam::kB)) << " | "
          << rate(x, calibrationMetric(m, CalibrationField::kInside3Sigma)) << " | "
          << rate(x, calibrationMetric(m, CalibrationField::kRefusalNamesFault)) << " |\n";
    }
    out << "\n";
  }
  const std::set<std::string> deskew = methods(groups, TrialSection::kDeskew);
  if (!deskew.empty()) {
    out << "### De-skew: mean point error [mm] (scans de-skewed)\n\n| condition |";
    for (const auto& m : deskew) out << " " << m << " |";
    out << "\n| :-- |";
    for (std::size_t i = 0; i < deskew.size(); ++i) out << " --: |";
    out << "\n";
    for (const auto& g : groups) {
      out << "| " << g.sweep.at(kFaultsEnable) << " |";
      for (const auto& m : deskew)
        out << " " << stat(g.metrics, deskewMetric(m, DeskewFigure::kMean), 1000.0) << " ("
            << rate(g.metrics, deskewMetric(m, DeskewField::kOk)) << " ok) |";
      out << "\n";
    }
    out << "\n`ok` is the share of trials in which the method de-skewed every scan.\n\n";
  }
  return out.str();
}

}  // namespace slamprep::eval
