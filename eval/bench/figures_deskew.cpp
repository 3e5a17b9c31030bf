#include <algorithm>
#include <cmath>
#include <map>

#include "slamprep/algo/deskew/deskew.hpp"
#include "slamprep/eval/bench/figure_groups.hpp"
#include "slamprep/eval/bench/figures_internal.hpp"
#include "slamprep/eval/bench/trial_metrics.hpp"

namespace slamprep::eval {
namespace {

constexpr const char* kOracleNote = "the oracle, at ~1e-12 mm, not drawn";

// De-skew methods of the groups in the order of algo::allDeskewMethods(), without the oracle
// (it would stretch a log axis over 10 decades; the tables report it).
std::vector<std::string> plottedDeskewMethods(const std::vector<SummaryGroup>& groups) {
  const auto present = deskewMethodsIn(groups);
  std::vector<std::string> out;
  for (const auto method : algo::allDeskewMethods()) {
    const std::string name(algo::deskewMethodName(method));
    if (method != algo::DeskewMethod::kOracle &&
        std::find(present.begin(), present.end(), name) != present.end())
      out.push_back(name);
  }
  return out;
}

}  // namespace

plot::Figure deskewFigure(const std::vector<SummaryGroup>& groups) {
  const auto methods = plottedDeskewMethods(groups);
  const int n = static_cast<int>(groups.size());
  // Wide panels: seven method names side by side under each.
  const int cols = n <= 3 ? 1 : 2, rows = (n + cols - 1) / cols;
  plot::Figure fig{.width_px = 1100 * cols + 40,
                   .height_px = 80 + 400 * rows,
                   .title = std::string("De-skew error against the ground-truth points, per "
                                        "condition (") +
                            kOracleNote + ")",
                   .rows = rows,
                   .cols = cols};
  for (const auto& g : groups) {
    const int seeds = seedsOf(g);
    plot::Axes axes{.title = conditionLabel(g, groups) + " (" + seedsNote(seeds) + ")",
                    .y_label = "mean point error [mm]",
                    .log_y = true,
                    .legend = plot::LegendPosition::None};
    axes.categories = methods;
    axes.dodge = false;  // one series per category
    // One series per method at its own category: its colour and marker, no dodging.
    for (std::size_t i = 0; i < methods.size(); ++i) {
      plot::Series dot = methodDots(deskewPalette(), methods[i]);
      dot.label.clear();  // the category names it
      pushMeanWithSpread(dot, static_cast<double>(i), g.metrics,
                         deskewMetric(methods[i], DeskewFigure::kMean), seeds, 1e3);
      axes.series.push_back(dot);
    }
    fig.axes.push_back(axes);
  }
  return fig;
}

std::optional<plot::Figure> deskewVsSpeedFigure(const std::vector<SummaryGroup>& groups) {
  if (!scenarioSeries(groups)) return std::nullopt;
  const auto methods = plottedDeskewMethods(groups);
  std::map<std::string, std::vector<const SummaryGroup*>, decltype(&naturalLess)> panels(
      naturalLess);
  for (const auto& g : groups) panels[otherSweepLabel(g, "")].push_back(&g);
  const int cols = static_cast<int>(panels.size());
  plot::Figure fig{.width_px = 640 * cols + 220,
                   .height_px = 700,
                   .title = "De-skew error vs driving speed (" +
                            seedsNote(seedsOf(groups.front())) + " per point; " + kOracleNote + ")",
                   .rows = 1,
                   .cols = cols};
  for (const auto& [label, members] : panels) {
    plot::Axes axes{.title = label.empty() ? "" : label,
                    .x_label = "mean speed [m/s]",
                    .y_label = "mean point error [mm]",
                    .log_y = true,
                    .legend = &label == &panels.rbegin()->first ? plot::LegendPosition::Outside
                                                                : plot::LegendPosition::None};
    std::vector<std::pair<double, const SummaryGroup*>> points;
    for (const SummaryGroup* g : members)
      points.push_back(
          {statOf(g->metrics, simMetric(SimField::kMeanSpeed), &MetricStats::mean), g});
    std::sort(points.begin(), points.end(),
              [](const auto& a, const auto& b) { return a.first < b.first; });
    for (const std::string& method : methods) {
      plot::Series line = methodDots(deskewPalette(), method);
      line.style = plot::Style::LineMarkers;
      // odom-quadratic lies on odom-linear at 100 Hz odometry: dashed over larger markers.
      line.dashed = method == "odom-quadratic";
      if (method == "odom-linear") line.marker_size_px = 14.0;
      for (const auto& [speed, g] : points) {
        pushMeanWithSpread(line, speed, g->metrics, deskewMetric(method, DeskewFigure::kMean),
                           seedsOf(*g), 1e3);
      }
      axes.series.push_back(line);
    }
    fig.axes.push_back(axes);
  }
  return fig;
}

}  // namespace slamprep::eval
