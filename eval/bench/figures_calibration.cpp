#include <algorithm>
#include <cmath>
#include <map>

#include "algo/calibration/calibration_method.hpp"
#include "eval/bench/figure_groups.hpp"
#include "eval/bench/figures_internal.hpp"

namespace slamprep::eval {
namespace {

using nlohmann::json;

struct Param {
  const char* key;    // abs_error/<key>
  const char* label;  // category label
};

struct PanelSpec {
  const char* title;
  const char* unit;
  std::vector<Param> params;
};

const std::vector<PanelSpec>& panelSpecs() {
  static const std::vector<PanelSpec> kPanels = {
      {"wheel geometry",
       "|error| [%]",
       {{"r_L_pct", "r_{L}"}, {"r_R_pct", "r_{R}"}, {"b_pct", "b"}}},
      {"lidar mount position", "|error| [mm]", {{"lidar_x_mm", "x"}, {"lidar_y_mm", "y"}}},
      {"lidar mount yaw", "|error| [deg]", {{"lidar_yaw_deg", "yaw"}}}};
  return kPanels;
}

// One panel of a group: a dot per method and parameter, the methods side by side; only the
// methods that estimate these parameters (direct and model have no mount).
plot::Axes calibrationPanel(const json& group, const PanelSpec& spec,
                            const std::vector<std::string>& methods, int seeds) {
  plot::Axes axes{.title = spec.title,
                  .y_label = spec.unit,
                  .log_y = true,
                  .legend = plot::LegendPosition::None};
  for (const Param& p : spec.params) axes.categories.push_back(p.label);
  const json& m = group["metrics"];
  for (const std::string& method : methods) {
    plot::Series dots = methodDots(calibrationPalette(), method);
    bool any = false;
    for (std::size_t i = 0; i < spec.params.size(); ++i) {
      const std::string path = "calibration/" + method + "/abs_error/" + spec.params[i].key;
      const double v = statOf(m, path, "mean");
      any = any || std::isfinite(v);
      pushMeanWithSpread(dots, static_cast<double>(i), m, path, seeds);
    }
    if (any) axes.series.push_back(dots);
  }
  return axes;
}

}  // namespace

plot::Figure calibrationFigure(const json& groups) {
  const auto methods = methodsIn(groups, "calibration", "ok");
  // A condition where every method refused (an arc has no excitation to calibrate from) gets
  // no row; the title says so.
  std::vector<const json*> shown;
  std::string left_out;
  for (const auto& g : groups) {
    bool any = false;
    for (const auto& method : methods)
      any = any || std::isfinite(
                       statOf(g["metrics"], "calibration/" + method + "/abs_error/b_pct", "mean"));
    if (any)
      shown.push_back(&g);
    else
      left_out += (left_out.empty() ? "" : ", ") + conditionLabel(g, groups);
  }
  const int rows = std::max<int>(1, shown.size());
  // The seeds in the figure title when every group has as many, else in each row's title.
  const std::string common = commonSeedsNote(groups);
  std::string title = "Calibration error against the simulated truth";
  if (!common.empty()) title += " (" + common + ")";
  if (!left_out.empty()) title += "; every method refused: " + left_out;
  plot::Figure fig{
      .width_px = 1600, .height_px = 70 + 330 * rows, .title = title, .rows = rows, .cols = 3};
  for (const json* group : shown) {
    const json& g = *group;
    const int seeds = g.value("trials", 1);
    const std::string condition =
        conditionLabel(g, groups) + (common.empty() ? " (" + seedsNote(seeds) + ")" : "");
    for (const PanelSpec& spec : panelSpecs()) {
      plot::Axes axes = calibrationPanel(g, spec, methods, seeds);
      if (&spec == &panelSpecs().front()) {
        axes.title = condition;  // the row's condition; the y label names the parameters
        if (group == shown.front())
          axes.legend = plot::LegendPosition::Outside;  // every method, beside the data
      }
      fig.axes.push_back(axes);
    }
  }
  return fig;
}

plot::Figure calibrationVsTimeFigure(const json& groups) {
  const std::vector<std::pair<std::string, std::string>> params = {
      {"b_pct", "b |error| [%]"},
      {"r_L_pct", "r_{L} |error| [%]"},
      {"r_R_pct", "r_{R} |error| [%]"},
      {"lidar_yaw_deg", "lidar yaw |error| [deg]"}};
  const auto methods = methodsIn(groups, "calibration", "ok");
  std::map<std::string, std::vector<const json*>, decltype(&naturalLess)> columns(naturalLess);
  for (const auto& g : groups) columns[otherSweepLabel(g, "duration_s")].push_back(&g);
  const auto duration = [](const json* g) {
    return std::stod((*g)["sweep"]["duration_s"].get<std::string>());
  };
  for (auto& [_, members] : columns)  // along the driving time
    std::sort(members.begin(), members.end(),
              [&](const json* a, const json* b) { return duration(a) < duration(b); });
  const int cols = static_cast<int>(columns.size());
  plot::Figure fig{.width_px = 560 * cols + 200,
                   .height_px = 1300,
                   .title = "Calibration error vs driving time (" +
                            seedsNote(groups.front().value("trials", 1)) + " per point)",
                   .rows = static_cast<int>(params.size()),
                   .cols = cols};
  for (const auto& [key, label] : params)
    for (const auto& [column, members] : columns) {
      plot::Axes axes{.title = column,
                      .x_label = "driving time [s]",
                      .y_label = label,
                      .log_y = true,
                      .legend = plot::LegendPosition::None};
      if (&column == &columns.rbegin()->first && key == params.front().first)
        axes.legend = plot::LegendPosition::Outside;
      for (const std::string& method : methods) {
        plot::Series line = methodDots(calibrationPalette(), method);
        line.style = plot::Style::LineMarkers;
        for (const json* g : members) {
          const std::string path = "calibration/" + method + "/abs_error/" + key;
          pushMeanWithSpread(line, duration(g), (*g)["metrics"], path, g->value("trials", 1));
        }
        if (std::any_of(line.y.begin(), line.y.end(), [](double v) { return std::isfinite(v); }))
          axes.series.push_back(line);
      }
      fig.axes.push_back(axes);
    }
  return fig;
}

}  // namespace slamprep::eval
