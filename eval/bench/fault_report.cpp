#include "eval/bench/fault_report.hpp"

#include <cstdio>
#include <set>
#include <sstream>

namespace slamprep::eval {
namespace {

using nlohmann::json;

// "mean ± std" of a group metric (scaled), or "-" when no trial has it.
std::string stat(const json& metrics, const std::string& path, double scale = 1.0) {
  if (!metrics.contains(path)) return "-";
  const json& m = metrics[path];
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.3g ± %.2g", scale * m["mean"].get<double>(),
                scale * m["std"].get<double>());
  return buf;
}

std::string rate(const json& metrics, const std::string& path) {
  if (!metrics.contains(path)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f %%", 100.0 * metrics[path]["mean"].get<double>());
  return buf;
}

// Methods present in any group under "calibration/<method>/" or "deskew/<method>/".
std::set<std::string> methods(const json& groups, const std::string& area) {
  std::set<std::string> out;
  for (const auto& g : groups)
    for (const auto& [path, v] : g["metrics"].items())
      if (path.rfind(area + "/", 0) == 0)
        out.insert(path.substr(area.size() + 1, path.find('/', area.size() + 1) - area.size() - 1));
  return out;
}

}  // namespace

std::string faultRobustnessSection(const json& summary) {
  if (!summary.contains("groups") || summary["groups"].empty()) return "";
  const json& groups = summary["groups"];
  for (const auto& g : groups)
    if (!g["sweep"].contains("faults.enable")) return "";
  std::ostringstream out;
  out << "## Robustness against faults\n\nPer condition (`faults.enable`, docs/faults.md), mean "
         "± standard deviation over the seeds. Errors are absolute, in % of the true value; "
         "`ok` counts trials where the method gave an estimate; `refused, naming the fault` "
         "counts refusals whose reason names a fault that was on.\n\n";
  for (const std::string& m : methods(groups, "calibration")) {
    const std::string p = "calibration/" + m + "/";
    out << "### Calibration: " << m << "\n\n| condition | ok | r_L err [%] | r_R err [%] | "
        << "b err [%] | truth in 3σ | refused, naming the fault |\n| :-- | --: | --: | --: | "
        << "--: | --: | --: |\n";
    for (const auto& g : groups) {
      const json& x = g["metrics"];
      out << "| " << g["sweep"]["faults.enable"].get<std::string>() << " | " << rate(x, p + "ok")
          << " | " << stat(x, p + "abs_error/r_L_pct") << " | " << stat(x, p + "abs_error/r_R_pct")
          << " | " << stat(x, p + "abs_error/b_pct") << " | " << rate(x, p + "inside_3sigma")
          << " | " << rate(x, p + "refusal_names_fault") << " |\n";
    }
    out << "\n";
  }
  const std::set<std::string> deskew = methods(groups, "deskew");
  if (!deskew.empty()) {
    out << "### De-skew: mean point error [mm] (scans de-skewed)\n\n| condition |";
    for (const auto& m : deskew) out << " " << m << " |";
    out << "\n| :-- |";
    for (std::size_t i = 0; i < deskew.size(); ++i) out << " --: |";
    out << "\n";
    for (const auto& g : groups) {
      out << "| " << g["sweep"]["faults.enable"].get<std::string>() << " |";
      for (const auto& m : deskew)
        out << " " << stat(g["metrics"], "deskew/" + m + "/mean_m", 1000.0) << " ("
            << rate(g["metrics"], "deskew/" + m + "/ok") << " ok) |";
      out << "\n";
    }
    out << "\n`ok` is the share of trials in which the method de-skewed every scan.\n\n";
  }
  return out.str();
}

}  // namespace slamprep::eval
