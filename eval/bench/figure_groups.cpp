#include "slamprep/eval/bench/figure_groups.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <regex>

#include "slamprep/algo/calibration/calibration_method.hpp"
#include "slamprep/algo/deskew/deskew.hpp"
#include "slamprep/eval/bench/trial_metrics.hpp"

namespace slamprep::eval {
namespace {

// Scenario files in words; others: the file's stem with spaces.
std::string scenarioWords(const std::string& file) {
  static const std::map<std::string, std::string> kKnown = {
      {"default", "Calibration drive"},
      {"calibration_3min", "3-minute calibration drive"},
      {"arc", "Circle arc, 1 m/s"},
      {"random_smooth", "Random smooth drive"},
      {"figure_eight", "Figure eight"},
      {"explore", "Exploration"},
      {"spin", "Spins"},
      {"stop_and_go", "Stop and go"}};
  const std::string stem = std::filesystem::path(file).stem().string();
  if (const auto it = kKnown.find(stem); it != kKnown.end()) return it->second;
  static const std::regex kCircle(R"(circle_v([0-9.]+))");
  std::smatch m;
  if (std::regex_match(stem, m, kCircle)) return "Circle at " + m[1].str() + " m/s";
  std::string words = stem;
  std::replace(words.begin(), words.end(), '_', ' ');
  if (!words.empty()) words[0] = static_cast<char>(std::toupper(words[0]));
  return words;
}

// A sweep value in words: "lidar 5 Hz", "120 s", "range noise 5 mm", "faults: all".
std::string sweepWords(const std::string& key, const std::string& value) {
  if (key == "lidar.rate_hz") return "lidar " + value + " Hz";
  if (key == "duration_s") return value + " s";
  if (key == "lidar.range_noise_m") {
    const double mm = std::stod(value) * 1e3;
    char text[32];
    std::snprintf(text, sizeof text, "range noise %g mm", mm);
    return text;
  }
  if (key == "faults.enable") {
    std::string v = value;
    std::replace(v.begin(), v.end(), '_', ' ');
    return v == "none" ? "no fault" : v == "all" ? "every fault" : v;
  }
  return key + " = " + value;
}

// Methods of `section` whose metric `metric(method)` is in any group, in first-seen order.
template <typename Metric>
std::vector<std::string> methodsWith(const std::vector<SummaryGroup>& groups, TrialSection section,
                                     const Metric& metric) {
  std::vector<std::string> out;
  for (const auto& g : groups)
    for (const auto& [path, _] : g.metrics) {
      const std::string method = methodOfMetric(section, path);
      if (!method.empty() && path == metric(method) &&
          std::find(out.begin(), out.end(), method) == out.end())
        out.push_back(method);
    }
  return out;
}

}  // namespace

std::string conditionLabel(const SummaryGroup& group, const std::vector<SummaryGroup>& groups) {
  const std::string& scenario = group.scenario;
  const bool scenarios_differ = std::any_of(
      groups.begin(), groups.end(), [&](const SummaryGroup& g) { return g.scenario != scenario; });
  std::string label = scenarios_differ ? scenarioWords(scenario) : "";
  for (const auto& [key, value] : group.sweep)
    label += (label.empty() ? "" : ", ") + sweepWords(key, value);
  return label.empty() ? scenarioWords(scenario) : label;
}

std::string seedsNote(int seeds) {
  return seeds <= 1 ? "1 seed" : "mean, min to max over " + std::to_string(seeds) + " seeds";
}

std::string boxSeedsNote(int seeds) {
  return "boxes: quartiles and median of " + std::to_string(seeds) +
         " seeds; whiskers: 1.5 IQR; dots: beyond";
}

void pushMeanWithSpread(plot::Series& s, double x, const SummaryMetrics& metrics,
                        const std::string& path, int seeds, double scale) {
  const double mean = scale * statOf(metrics, path, &MetricStats::mean);
  const bool spread = seeds >= 2 && std::isfinite(mean);
  s.x.push_back(x);
  s.y.push_back(mean);
  s.y_err.push_back(spread ? scale * statOf(metrics, path, &MetricStats::max) - mean : 0.0);
  s.y_err_low.push_back(spread ? mean - scale * statOf(metrics, path, &MetricStats::min) : 0.0);
}

double statOf(const SummaryMetrics& metrics, const std::string& path, double MetricStats::*stat) {
  const auto it = metrics.find(path);
  return it != metrics.end() ? it->second.*stat : std::nan("");
}

int seedsOf(const SummaryGroup& group) {
  return static_cast<int>(group.trials);
}

std::vector<std::string> calibrationMethodsIn(const std::vector<SummaryGroup>& groups) {
  return methodsWith(groups, TrialSection::kCalibration, [](const std::string& method) {
    return calibrationMetric(method, CalibrationField::kOk);
  });
}

std::vector<std::string> deskewMethodsIn(const std::vector<SummaryGroup>& groups) {
  return methodsWith(groups, TrialSection::kDeskew, [](const std::string& method) {
    return deskewMetric(method, DeskewFigure::kMean);
  });
}

const std::vector<std::string>& calibrationPalette() {
  static const std::vector<std::string> kAll = [] {
    std::vector<std::string> all;
    for (const auto method : algo::allCalibrationMethods())
      all.emplace_back(algo::calibrationMethodName(method));
    return all;
  }();
  return kAll;
}

const std::vector<std::string>& deskewPalette() {
  static const std::vector<std::string> kAll = [] {
    std::vector<std::string> all;
    for (const auto method : algo::allDeskewMethods())
      if (method != algo::DeskewMethod::kOracle) all.emplace_back(algo::deskewMethodName(method));
    return all;
  }();
  return kAll;
}

plot::Color methodColor(const std::vector<std::string>& all, const std::string& method) {
  return plot::paletteColor(std::find(all.begin(), all.end(), method) - all.begin());
}

plot::Marker methodMarker(const std::vector<std::string>& all, const std::string& method) {
  static const plot::Marker kShapes[] = {plot::Marker::Circle,       plot::Marker::Square,
                                         plot::Marker::Triangle,     plot::Marker::Diamond,
                                         plot::Marker::TriangleDown, plot::Marker::Plus,
                                         plot::Marker::Cross};
  const auto i = static_cast<std::size_t>(std::find(all.begin(), all.end(), method) - all.begin());
  return kShapes[i % std::size(kShapes)];
}

plot::Series methodDots(const std::vector<std::string>& all, const std::string& method) {
  return {.label = method,
          .style = plot::Style::Markers,
          .color = methodColor(all, method),
          .marker_size_px = 9.0,
          .marker = methodMarker(all, method)};
}

std::optional<std::vector<double>> scenarioSeries(const std::vector<SummaryGroup>& groups) {
  static const std::regex kNumbered(R"((.*[^0-9.])([0-9]+(\.[0-9]+)?))");
  std::optional<std::string> stem;
  std::vector<double> values;
  for (const auto& g : groups) {
    const std::string s = std::filesystem::path(g.scenario).stem().string();
    std::smatch m;
    if (!std::regex_match(s, m, kNumbered)) return std::nullopt;
    if (stem && *stem != m[1].str()) return std::nullopt;
    stem = m[1].str();
    values.push_back(std::stod(m[2].str()));
  }
  std::vector<double> distinct = values;
  std::sort(distinct.begin(), distinct.end());
  if (std::unique(distinct.begin(), distinct.end()) - distinct.begin() < 3) return std::nullopt;
  return values;
}

bool naturalLess(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    const bool da = std::isdigit(static_cast<unsigned char>(a[i])) != 0;
    const bool db = std::isdigit(static_cast<unsigned char>(b[j])) != 0;
    if (da && db) {
      std::size_t ei = i, ej = j;
      const double x = std::stod(a.substr(i), &ei), y = std::stod(b.substr(j), &ej);
      if (x != y) return x < y;
      i += ei, j += ej;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i, ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

std::string commonSeedsNote(const std::vector<SummaryGroup>& groups) {
  if (groups.empty()) return "";
  const int seeds = seedsOf(groups.front());
  for (const auto& g : groups)
    if (seedsOf(g) != seeds) return "";
  return seedsNote(seeds);
}

std::string otherSweepLabel(const SummaryGroup& group, const std::string& axis) {
  std::string label;
  for (const auto& [key, value] : group.sweep)
    if (key != axis) label += (label.empty() ? "" : ", ") + sweepWords(key, value);
  return label;
}

}  // namespace slamprep::eval
