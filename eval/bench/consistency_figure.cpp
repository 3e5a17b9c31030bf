#include "slamprep/eval/bench/consistency_figure.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <map>
#include <numbers>
#include <set>
#include <string>

#include "slamprep/eval/bench/figure_groups.hpp"
#include "slamprep/eval/bench/trial_metrics.hpp"

namespace slamprep::eval {
namespace {

constexpr double kRange = 5.0;     // histogram over error/sigma in [-5, 5]
constexpr double kBinWidth = 0.5;  // 20 bins: ~5 runs per central bin at 100 seeds

struct Parameter {
  CalibrationParam param;
  const char* title;  // panel title
};
constexpr Parameter kParameters[] = {{CalibrationParam::kRL, "Left wheel radius r_{L}"},
                                     {CalibrationParam::kRR, "Right wheel radius r_{R}"},
                                     {CalibrationParam::kB, "Wheel base b"},
                                     {CalibrationParam::kMountX, "Lidar mount x"},
                                     {CalibrationParam::kMountY, "Lidar mount y"},
                                     {CalibrationParam::kMountYaw, "Lidar mount yaw"}};

// error / sigma of one method and parameter over the trials that did not refuse.
std::vector<double> normalizedErrors(const std::vector<std::map<std::string, double>>& rows,
                                     const std::string& method, CalibrationParam param) {
  std::vector<double> out;
  const std::string ok_path = calibrationMetric(method, CalibrationField::kOk),
                    error_path = calibrationMetric(method, CalibrationError::kSigned, param),
                    sigma_path = calibrationMetric(method, CalibrationError::kSigma, param);
  for (const auto& row : rows) {
    const auto ok = row.find(ok_path), error = row.find(error_path), sigma = row.find(sigma_path);
    if (ok == row.end() || ok->second != 1.0 || error == row.end() || sigma == row.end() ||
        !(sigma->second > 0.0))
      continue;
    out.push_back(error->second / sigma->second);
  }
  return out;
}

std::vector<std::string> splitCsvLine(const std::string& line) {
  std::vector<std::string> out(1);
  for (char c : line) {
    if (c == ',')
      out.emplace_back();
    else
      out.back() += c;
  }
  return out;
}

// Outline of the histogram as a density (count / (n * bin width)); runs beyond the range fall
// in the end bins, so the area stays 1.
plot::Series stepHistogram(const std::vector<double>& z) {
  const int bins = static_cast<int>(std::lround(2 * kRange / kBinWidth));
  std::vector<int> counts(bins, 0);
  for (double v : z)
    ++counts[std::clamp(static_cast<int>(std::floor((v + kRange) / kBinWidth)), 0, bins - 1)];
  plot::Series s{.style = plot::Style::Line};
  for (int i = 0; i < bins; ++i) {
    const double density = counts[i] / (z.size() * kBinWidth);
    const double left = -kRange + i * kBinWidth;
    s.x.insert(s.x.end(), {left, left + kBinWidth});
    s.y.insert(s.y.end(), {density, density});
  }
  s.x.insert(s.x.begin(), -kRange);
  s.y.insert(s.y.begin(), 0.0);
  s.x.push_back(kRange);
  s.y.push_back(0.0);
  return s;
}

plot::Series normalDensity() {
  plot::Series s{.label = "unit normal",
                 .style = plot::Style::Line,
                 .color = plot::rgb(0x000000),
                 .dashed = true};
  for (int i = 0; i <= 200; ++i) {
    const double x = -kRange + i * (2 * kRange / 200);
    s.x.push_back(x);
    s.y.push_back(std::exp(-0.5 * x * x) / std::sqrt(2 * std::numbers::pi));
  }
  return s;
}

bool offScale(const std::vector<double>& z) {
  const auto inside =
      std::count_if(z.begin(), z.end(), [](double v) { return std::abs(v) <= kRange; });
  return 2 * inside < static_cast<std::ptrdiff_t>(z.size());
}

}  // namespace

std::vector<std::map<std::string, double>> readTrialRows(const std::filesystem::path& trials_csv) {
  std::vector<std::map<std::string, double>> rows;
  std::ifstream in(trials_csv);
  std::string line;
  if (!std::getline(in, line)) return rows;
  const auto header = splitCsvLine(line);
  constexpr std::size_t kTextColumns = 4;  // id, world, scenario, seed
  while (std::getline(in, line)) {
    const auto cells = splitCsvLine(line);
    auto& row = rows.emplace_back();
    for (std::size_t i = kTextColumns; i < cells.size() && i < header.size(); ++i)
      if (!cells[i].empty()) row[header[i]] = std::strtod(cells[i].c_str(), nullptr);
  }
  return rows;
}

std::vector<std::string> readTrialIds(const std::filesystem::path& trials_csv) {
  std::vector<std::string> ids;
  std::ifstream in(trials_csv);
  std::string line;
  if (!std::getline(in, line)) return ids;  // the header
  while (std::getline(in, line)) ids.push_back(line.substr(0, line.find(',')));
  return ids;
}

std::optional<plot::Figure> consistencyFigure(
    const std::vector<std::map<std::string, double>>& trial_rows) {
  std::set<std::string> methods;  // those that reported a sigma
  const std::string sigma = std::string(nameOf(kCalibrationErrorKeys, CalibrationError::kSigma));
  for (const auto& row : trial_rows)
    for (const auto& [path, _] : row) {
      const std::string method = methodOfMetric(TrialSection::kCalibration, path);
      if (!method.empty() &&
          path.rfind(methodPrefix(TrialSection::kCalibration, method) + sigma + "/", 0) == 0)
        methods.insert(method);
    }
  if (methods.empty()) return std::nullopt;
  std::set<std::string> off_scale;
  // Legends beside each panel, never over a histogram: the figure is wide enough for three.
  plot::Figure fig{.width_px = 2100, .height_px = 950, .rows = 2, .cols = 3};
  for (const auto& param : kParameters) {
    plot::Axes axes{.title = param.title,
                    .x_label = "error / reported σ",
                    .y_label = "density",
                    .x_range = plot::Range{-kRange, kRange},
                    .legend = plot::LegendPosition::Outside};
    for (const auto& method : methods) {
      const auto z = normalizedErrors(trial_rows, method, param.param);
      if (z.empty()) continue;
      if (offScale(z)) {
        off_scale.insert(method);
        continue;
      }
      plot::Series s = stepHistogram(z);
      s.label = method + " (n = " + std::to_string(z.size()) + ")";
      s.color = methodColor(calibrationPalette(), method);  // as in every figure
      axes.series.push_back(std::move(s));
    }
    axes.series.push_back(normalDensity());
    fig.axes.push_back(std::move(axes));
  }
  fig.title =
      "Calibration error in units of the reported σ, per trial (|error/σ| > 5 in the end bins)";
  if (!off_scale.empty()) {
    std::string names;
    for (const auto& m : off_scale) names += (names.empty() ? "" : ", ") + m;
    fig.title += "; not drawn where most are beyond ±5σ: " + names;
  }
  return fig;
}

}  // namespace slamprep::eval
