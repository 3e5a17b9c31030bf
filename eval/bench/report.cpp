#include "slamprep/eval/bench/report.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <sstream>

#include "slamprep/eval/bench/fault_report.hpp"
#include "slamprep/eval/bench/group_consistency.hpp"
#include "slamprep/eval/bench/trial_metrics.hpp"

namespace slamprep::eval {
namespace {

// A table: a header row and rows of cells; rendered as Markdown or aligned text.
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
};

std::string fmt(double v, int digits = 3) {
  if (!std::isfinite(v)) return "-";
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

// "mean ± std" of a summary metric, scaled; "-" where absent.
std::string cell(const SummaryMetrics& metrics, const std::string& path, double scale = 1.0,
                 int digits = 3) {
  const auto it = metrics.find(path);
  if (it == metrics.end()) return "-";
  const MetricStats& m = it->second;
  const double mean = m.mean * scale, sd = m.std * scale;
  return m.n > 1 ? fmt(mean, digits) + " ± " + fmt(sd, 2) : fmt(mean, digits);
}

std::string percent(const SummaryMetrics& metrics, const std::string& path) {
  const auto it = metrics.find(path);
  if (it == metrics.end()) return "-";
  return fmt(100.0 * it->second.mean, 3) + " %";
}

// Method names under a section ("calibration/<method>/...") in first-seen order of the paths.
std::vector<std::string> methodsOf(const SummaryMetrics& metrics, TrialSection section) {
  std::vector<std::string> out;
  std::set<std::string> seen;
  for (const auto& [path, _] : metrics) {
    const std::string method = methodOfMetric(section, path);
    if (!method.empty() && seen.insert(method).second) out.push_back(method);
  }
  return out;
}

Table calibrationTable(const SummaryMetrics& m) {
  Table t{{"method", "ok", "r_L err [%]", "r_R err [%]", "b err [%]", "lidar x err [mm]",
           "lidar y err [mm]", "lidar yaw err [deg]", "truth in 3σ", "drift after [m]"},
          {}};
  for (const auto& method : methodsOf(m, TrialSection::kCalibration)) {
    std::vector<std::string> row = {method,
                                    percent(m, calibrationMetric(method, CalibrationField::kOk))};
    for (const CalibrationParam p : kCalibrationParams)
      row.push_back(cell(m, calibrationMetric(method, CalibrationError::kAbs, p)));
    row.push_back(percent(m, calibrationMetric(method, CalibrationField::kInside3Sigma)));
    row.push_back(cell(m, calibrationMetric(method, CalibrationField::kDrift)));
    t.rows.push_back(std::move(row));
  }
  return t;
}

Table deskewTable(const SummaryMetrics& m) {
  Table t{{"method", "ok", "mean [mm]", "RMS [mm]", "p95 [mm]", "max [mm]", "rotation part [mm]",
           "translation part [mm]"},
          {}};
  for (const auto& method : methodsOf(m, TrialSection::kDeskew)) {
    std::vector<std::string> row = {method, percent(m, deskewMetric(method, DeskewField::kOk))};
    for (const DeskewFigure f :
         {DeskewFigure::kMean, DeskewFigure::kRms, DeskewFigure::kP95, DeskewFigure::kMax,
          DeskewFigure::kRotationMean, DeskewFigure::kTranslationMean})
      row.push_back(cell(m, deskewMetric(method, f), 1e3));
    t.rows.push_back(std::move(row));
  }
  return t;
}

// One line per de-skew method that refused scans, "odom-linear: 12 scans refused in 2 trial(s)
// (not-bracketed 10, sample-gap 2)"; empty when none did. The error figures leave them out.
std::string refusalLines(const SummaryMetrics& m, const std::string& bullet) {
  const auto total = [&](const std::string& path) {  // mean over the trials that have the key
    const MetricStats& s = m.at(path);
    return std::to_string(std::lround(s.mean * static_cast<double>(s.n)));
  };
  std::string out;
  for (const auto& method : methodsOf(m, TrialSection::kDeskew)) {
    const std::string refused = deskewMetric(method, DeskewField::kRefusedScans);
    if (!m.contains(refused)) continue;
    const std::string by_reason = deskewRefusalMetric(method, "");
    std::string reasons;
    for (const auto& [path, _] : m)
      if (path.rfind(by_reason, 0) == 0)
        reasons +=
            (reasons.empty() ? "" : ", ") + path.substr(by_reason.size()) + " " + total(path);
    out += bullet + method + ": " + total(refused) + " scans refused in " +
           std::to_string(m.at(refused).n) + " trial(s) (" + reasons + ")\n";
  }
  return out;
}

// Dead reckoning with each geometry: the nominal one, the true one (slip and quantisation only)
// and every calibrated one.
Table odometryTable(const SummaryMetrics& m) {
  Table t{{"geometry", "APE RMSE [m]", "APE max [m]", "RPE per m, translation [mm]",
           "RPE per m, rotation [deg]"},
          {}};
  // `metric` names a field of one geometry's OdometryRecord.
  const auto row = [&](const std::string& label, const auto& metric) {
    if (!m.contains(metric(OdometryField::kApeRmse))) return;
    t.rows.push_back({label, cell(m, metric(OdometryField::kApeRmse)),
                      cell(m, metric(OdometryField::kApeMax)),
                      cell(m, metric(OdometryField::kRpeTransRmse), 1e3),
                      cell(m, metric(OdometryField::kRpeRotRmse))});
  };
  const auto raw = [](OdometryGeometry geometry) {
    return [geometry](OdometryField f) { return odometryMetric(geometry, f); };
  };
  row("nominal", raw(OdometryGeometry::kNominal));
  for (const auto& method : methodsOf(m, TrialSection::kCalibration))
    row("calibrated: " + method, [&](OdometryField f) { return calibrationMetric(method, f); });
  row("true", raw(OdometryGeometry::kTrue));
  return t;
}

Table simulationTable(const SummaryMetrics& m) {
  return {
      {"quantity", "mean ± std over trials"},
      {{"simulated time [s]", cell(m, simMetric(SimField::kDuration))},
       {"scans", cell(m, simMetric(SimField::kScans))},
       {"distance driven [m]", cell(m, simMetric(SimField::kDistance))},
       {"turned [rad]", cell(m, simMetric(SimField::kTurned))},
       {"final drift, nominal geometry [m]", cell(m, simMetric(SimField::kDriftNominal))},
       {"final drift, true geometry [m]", cell(m, simMetric(SimField::kDriftTrue))},
       {"scan-match translation error [mm]",
        cell(m, matchingMetric(MatchingField::kTransErrorRmse), 1e3)},
       {"scan-match rotation error [deg]", cell(m, matchingMetric(MatchingField::kRotErrorRmse))},
       {"scan matches converged", percent(m, matchingMetric(MatchingField::kConvergedFraction))}}};
}

std::string markdown(const Table& t) {
  std::ostringstream out;
  const auto row = [&](const std::vector<std::string>& cells) {
    out << "|";
    for (const auto& c : cells) out << " " << c << " |";
    out << "\n";
  };
  row(t.header);
  out << "|";
  for (std::size_t i = 0; i < t.header.size(); ++i) out << (i == 0 ? " :-- |" : " --: |");
  out << "\n";
  for (const auto& r : t.rows) row(r);
  return out.str();
}

// Display width of UTF-8 text (counts code points; enough for ± and σ).
std::size_t width(const std::string& s) {
  std::size_t n = 0;
  for (unsigned char c : s) n += (c & 0xC0) != 0x80;
  return n;
}

std::string aligned(const Table& t) {
  std::vector<std::size_t> w(t.header.size(), 0);
  for (std::size_t i = 0; i < w.size(); ++i) {
    w[i] = width(t.header[i]);
    for (const auto& r : t.rows) w[i] = std::max(w[i], width(r[i]));
  }
  std::ostringstream out;
  const auto row = [&](const std::vector<std::string>& cells) {
    for (std::size_t i = 0; i < cells.size(); ++i) {
      const std::string pad(w[i] - width(cells[i]), ' ');
      out << (i == 0 ? cells[i] + pad : pad + cells[i]) << (i + 1 < cells.size() ? "  " : "\n");
    }
  };
  row(t.header);
  for (const auto& r : t.rows) row(r);
  return out.str();
}

// "default" or "circle_v1.0, lidar.rate_hz=5": what distinguishes a group.
std::string groupName(const SummaryGroup& group) {
  std::string name = std::filesystem::path(group.scenario).stem().string();
  const std::string world = std::filesystem::path(group.world).stem().string();
  if (world != "room") name += " in " + world;
  for (const auto& [key, value] : group.sweep) name += ", " + key + "=" + value;
  return name;
}

// Per sweep point when there are a few (mixing scenarios would blur what each one shows);
// otherwise the whole suite at once and the plots for the breakdown.
constexpr std::size_t kMaxGroupSections = 8;

using Sections = std::vector<std::pair<std::string, const SummaryMetrics*>>;

Sections sections(const SuiteSummary& summary) {
  const auto& groups = summary.groups;
  Sections out;
  if (groups.size() > 1 && groups.size() <= kMaxGroupSections)
    for (const auto& g : groups) out.emplace_back(groupName(g), &g.metrics);
  else
    out.emplace_back("", &summary.metrics);
  return out;
}

// Seeds per group below which coverage and NEES are too noisy to print (1/n steps).
constexpr std::size_t kMinConsistencyTrials = 10;

// Bias, spread, RMS and coverage of each method's signed error against its reported sigma over
// the seeds of one group, and the mean NEES (summary "consistency", docs/results.md).
Table consistencyTable(const GroupConsistency& c) {
  static const EnumNames<CalibrationParam, kCalibrationParams.size()> kLabels = {
      {{CalibrationParam::kRL, "r_L [%]"},
       {CalibrationParam::kRR, "r_R [%]"},
       {CalibrationParam::kB, "b [%]"},
       {CalibrationParam::kMountX, "lidar x [mm]"},
       {CalibrationParam::kMountY, "lidar y [mm]"},
       {CalibrationParam::kMountYaw, "lidar yaw [deg]"}}};
  Table t{{"method", "parameter", "n", "bias", "std", "RMS", "within 1σ", "within 3σ"}, {}};
  for (const auto& [method, m] : c)
    for (const auto& [param, label] : kLabels) {
      const auto it = m.params.find(param);
      if (it == m.params.end()) continue;
      const ErrorConsistency& e = it->second;
      t.rows.push_back({method, std::string(label), fmt(e.n), fmt(e.bias), fmt(e.std), fmt(e.rms),
                        fmt(e.coverage_1sigma * 100) + " %", fmt(e.coverage_3sigma * 100) + " %"});
    }
  return t;
}

// Mean NEES per method beside the value an honest covariance gives (its dimension).
Table neesTable(const GroupConsistency& c) {
  Table t{{"method", "n", "mean NEES", "honest (dimension)"}, {}};
  for (const auto& [method, m] : c)
    if (m.nees)
      t.rows.push_back({method, fmt(static_cast<double>(m.nees->n)), fmt(m.nees->mean),
                        std::to_string(m.params.size())});
  return t;
}

std::string consistencySections(const SuiteSummary& summary) {
  std::string out;
  const auto& groups = summary.groups;
  if (groups.size() > kMaxGroupSections) return out;
  for (const auto& g : groups) {
    if (g.consistency.empty() || g.trials < kMinConsistencyTrials) continue;
    if (groups.size() > 1) out += "### " + groupName(g) + "\n\n";
    out += markdown(consistencyTable(g.consistency)) + "\n" + markdown(neesTable(g.consistency)) +
           "\n";
  }
  return out;
}

// One Markdown table per section, under the section's heading when there are several.
std::string perSection(const Sections& parts, Table (*table)(const SummaryMetrics&)) {
  std::string out;
  for (const auto& [name, metrics] : parts)
    out += (name.empty() ? "" : "### " + name + "\n\n") + markdown(table(*metrics)) + "\n";
  return out;
}

// The title and what the suite ran: its trials, how to reproduce it, the ones missing.
std::string reportHeader(const Suite& suite, const SuiteSummary& summary) {
  std::ostringstream out;
  out << "# Suite `" << suite.name << "`\n\n";
  if (!suite.description.empty()) out << suite.description << "\n\n";
  out << summary.trials << " trials: " << suite.worlds.size() << " world(s) x "
      << suite.scenarios.size() << " scenario(s)";
  for (const auto& axis : suite.sweep) out << " x " << axis.values.size() << " " << axis.key;
  out << " x " << suite.seeds << " seed(s), " << suite.mode << " mode, calibration motion from "
      << suite.motion << ".\nReproduce with `slamprep bench --suite " << suite.name
      << "`. Figures are mean ± standard deviation over trials; errors are absolute.\n\n";
  if (const std::size_t missing = summary.missing.size())
    out << "**Missing trials:** " << missing << " (failed or not yet run).\n\n";
  return out.str();
}

}  // namespace

std::string renderReport(const Suite& suite, const SuiteSummary& summary,
                         const std::vector<std::string>& plots) {
  const SummaryMetrics& m = summary.metrics;
  std::ostringstream out;
  out << reportHeader(suite, summary);
  const auto parts = sections(summary);
  const bool any_calibration = !methodsOf(m, TrialSection::kCalibration).empty();
  const bool any_deskew = !methodsOf(m, TrialSection::kDeskew).empty();
  if (any_calibration) {
    out << "## Calibration\n\nAbsolute error of each method's estimate against the geometry "
           "Bullet simulated (relative for r_L, r_R, b). A method that refuses (ill-conditioned "
           "data) counts against `ok` and is left out of the errors.\n\n";
    out << perSection(parts, calibrationTable);
  }
  if (const std::string c = consistencySections(summary); !c.empty()) {
    out << "## Consistency\n\nIs the reported σ honest? Over the seeds of one group: the signed "
           "error's mean (bias), standard deviation and RMS, the fraction of seeds whose |error| "
           "is within 1σ and 3σ of the σ the method reported (68.3 % and 99.7 % if honest), and "
           "the mean normalised estimation error squared with the full reported covariance "
           "(its dimension if honest: 6 with the mount, 3 without). Units: % of the true value "
           "for r_L, r_R, b.\n\n"
        << c;
  }
  if (any_deskew) {
    out << "## De-skew\n\nDistance of each corrected point to the ground-truth undistorted point "
           "of the same beam (range noise cancels), in millimetres, and the same error split by "
           "its cause: the part the method's rotation error explains and the part its translation "
           "error explains (docs/metrics.md).\n\n";
    out << perSection(parts, deskewTable);
    if (const std::string r = refusalLines(m, "- "); !r.empty())
      out << "Scans refused, left out of the figures (trials/<id>.json lists each):\n\n"
          << r << "\n";
  }
  if (!odometryTable(m).rows.empty()) {
    out << "## Odometry\n\nWheel odometry integrated with each geometry against the ground "
           "truth, as evo computes it: APE on positions with the first poses put together "
           "(`--align_origin`), RPE over consecutive 1 m stretches of path. The true geometry "
           "shows what slip and encoder quantisation alone leave.\n\n";
    out << perSection(parts, odometryTable);
  }
  out << faultRobustnessSection(summary);  // "" unless the suite sweeps faults.enable
  out << "## Simulation and scan matching\n\n";
  out << perSection(parts, simulationTable);
  if (!plots.empty()) {
    out << "## Plots\n\n";
    for (const auto& p : plots) out << "![" << p << "](plots/" << p << ")\n\n";
  }
  out << "Files: `summary.json` (schema in docs/results.md), `trials.csv` (one row per trial), "
         "`trials/` (one JSON per trial).\n";
  return out.str();
}

std::string renderConsoleSummary(const SuiteSummary& summary) {
  std::string out;
  for (const auto& [name, metrics] : sections(summary)) {
    if (!name.empty()) out += "== " + name + " ==\n";
    if (!methodsOf(*metrics, TrialSection::kCalibration).empty())
      out += "Calibration (absolute error vs truth)\n" + aligned(calibrationTable(*metrics)) + "\n";
    if (!methodsOf(*metrics, TrialSection::kDeskew).empty())
      out += "De-skew (point error vs ground truth)\n" + aligned(deskewTable(*metrics)) + "\n" +
             refusalLines(*metrics, "refused: ");
    if (const Table t = odometryTable(*metrics); !t.rows.empty())
      out += "Odometry (vs ground truth)\n" + aligned(t) + "\n";
    out += aligned(simulationTable(*metrics)) + "\n";
  }
  return out;
}

}  // namespace slamprep::eval
