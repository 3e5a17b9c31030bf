#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>

#include "slamprep/algo/calibration/calibration_method.hpp"
#include "slamprep/eval/bench/figure_groups.hpp"
#include "slamprep/eval/bench/figures_internal.hpp"
#include "slamprep/eval/bench/trial_metrics.hpp"

namespace slamprep::eval {
namespace {

struct Param {
  CalibrationParam param;
  const char* label;  // category label
};

struct PanelSpec {
  const char* title;
  const char* unit;  // "[%]": the y label is "|error| [%]" or, signed, "error [%]"
  std::vector<Param> params;
};

const std::vector<PanelSpec>& panelSpecs() {
  static const std::vector<PanelSpec> kPanels = {
      {"wheel geometry",
       "[%]",
       {{CalibrationParam::kRL, "r_{L}"},
        {CalibrationParam::kRR, "r_{R}"},
        {CalibrationParam::kB, "b"}}},
      {"lidar mount position",
       "[mm]",
       {{CalibrationParam::kMountX, "x"}, {CalibrationParam::kMountY, "y"}}},
      {"lidar mount yaw", "[deg]", {{CalibrationParam::kMountYaw, "yaw"}}}};
  return kPanels;
}

// One panel of a group: a dot per method and parameter, the methods side by side; only the
// methods that estimate these parameters (direct and model have no mount).
plot::Axes calibrationPanel(const SummaryGroup& group, const PanelSpec& spec,
                            const std::vector<std::string>& methods, int seeds) {
  plot::Axes axes{.title = spec.title,
                  .y_label = std::string("|error| ") + spec.unit,
                  .log_y = true,
                  .legend = plot::LegendPosition::None};
  for (const Param& p : spec.params) axes.categories.push_back(p.label);
  const SummaryMetrics& m = group.metrics;
  for (const std::string& method : methods) {
    plot::Series dots = methodDots(calibrationPalette(), method);
    bool any = false;
    for (std::size_t i = 0; i < spec.params.size(); ++i) {
      const std::string path =
          calibrationMetric(method, CalibrationError::kAbs, spec.params[i].param);
      const double v = statOf(m, path, &MetricStats::mean);
      any = any || std::isfinite(v);
      pushMeanWithSpread(dots, static_cast<double>(i), m, path, seeds);
    }
    if (any) axes.series.push_back(dots);
  }
  return axes;
}

// ---- box plots of the signed error (groups with many seeds) ----

// A box reaching this many times as far from zero as the best method's widest box would squash
// every other box into a line; it gets a panel of its own.
constexpr double kOffScale = 20.0;

using BoxKey = std::pair<std::string, std::size_t>;  // method, parameter index

std::vector<double> signedErrors(const TrialRows& rows, const std::string& method,
                                 CalibrationParam param) {
  const std::string path = calibrationMetric(method, CalibrationError::kSigned, param);
  std::vector<double> values;
  for (const auto& row : rows)
    if (const auto it = row.find(path); it != row.end()) values.push_back(it->second);
  return values;
}

// How far a box plot reaches from zero: its larger whisker.
double reachOf(const std::vector<double>& sample) {
  const plot::BoxStats b = plot::boxStats(sample);
  return std::max(std::abs(b.whisker_low), std::abs(b.whisker_high));
}

// The boxes of a panel that are off the others' scale in any group, so that every row splits its
// panels alike.
std::set<BoxKey> offScaleBoxes(const std::vector<const TrialRows*>& rows, const PanelSpec& spec,
                               const std::vector<std::string>& methods) {
  std::set<BoxKey> off;
  for (const TrialRows* trials : rows) {
    std::map<BoxKey, double> reach;
    std::map<std::string, double> widest;  // per method
    for (const std::string& method : methods)
      for (std::size_t i = 0; i < spec.params.size(); ++i) {
        const auto values = signedErrors(*trials, method, spec.params[i].param);
        if (values.empty()) continue;
        reach[{method, i}] = reachOf(values);
        widest[method] = std::max(widest[method], reach[{method, i}]);
      }
    if (widest.empty()) continue;
    const double best = std::min_element(widest.begin(), widest.end(), [](auto& a, auto& b) {
                          return a.second < b.second;
                        })->second;
    for (const auto& [box, r] : reach)
      if (r > kOffScale * best) off.insert(box);
  }
  return off;
}

// "direct, off the others' scale": the methods of the off-scale boxes of a panel.
std::string offScaleTitle(const std::set<BoxKey>& off) {
  std::vector<std::string> names;
  for (const auto& [method, _] : off)
    if (std::find(names.begin(), names.end(), method) == names.end()) names.push_back(method);
  std::string title;
  for (std::size_t k = 0; k < names.size(); ++k)
    title += (k == 0 ? "" : k + 1 == names.size() ? " and " : ", ") + names[k];
  return title + ", off the others' scale";
}

// "r_{L} (median +6.87 %)": an off-scale box's median, written out because its own scale is
// often too coarse to read it; only the name when several methods share the slot.
std::string offScaleLabel(const TrialRows& trials, const PanelSpec& spec, std::size_t i,
                          const std::set<BoxKey>& off) {
  std::vector<std::string> methods;
  for (const auto& [method, param] : off)
    if (param == i) methods.push_back(method);
  const std::string name = spec.params[i].label;
  if (methods.size() != 1) return name;
  const double median =
      plot::boxStats(signedErrors(trials, methods[0], spec.params[i].param)).median;
  char value[32];
  std::snprintf(value, sizeof value, "%.3g", std::abs(median));
  const std::string unit = std::string(spec.unit).substr(1, std::strlen(spec.unit) - 2);
  return name + " (median " + (median < 0 ? "\xE2\x88\x92" : "+") + value + " " + unit + ")";
}

// Box plots of one group's signed errors, the methods side by side: the boxes within the common
// scale (`off_panel` false, every parameter) or only those off it (true, their parameters).
plot::Axes boxPanel(const TrialRows& trials, const PanelSpec& spec,
                    const std::vector<std::string>& methods, const std::set<BoxKey>& off,
                    bool off_panel) {
  plot::Axes axes{.title = off_panel ? offScaleTitle(off) : spec.title,
                  .y_label = std::string("error ") + spec.unit,
                  .legend = plot::LegendPosition::None};
  std::vector<std::size_t> params;
  for (std::size_t i = 0; i < spec.params.size(); ++i)
    if (!off_panel ||
        std::any_of(off.begin(), off.end(), [&](const BoxKey& b) { return b.second == i; }))
      params.push_back(i);
  for (const std::size_t i : params)
    axes.categories.push_back(off_panel ? offScaleLabel(trials, spec, i, off)
                                        : std::string(spec.params[i].label));
  for (const std::string& method : methods) {
    plot::Series boxes = methodDots(calibrationPalette(), method);
    boxes.style = plot::Style::Box;
    boxes.marker_size_px = 4.0;
    for (std::size_t k = 0; k < params.size(); ++k) {
      if (off.contains({method, params[k]}) != off_panel) continue;
      for (const double v : signedErrors(trials, method, spec.params[params[k]].param))
        boxes.x.push_back(static_cast<double>(k)), boxes.y.push_back(v);
    }
    if (!boxes.y.empty()) axes.series.push_back(boxes);
  }
  // Zero error, below the boxes: where a bias shows.
  const double right = static_cast<double>(params.size()) - 0.5;
  axes.segments.push_back(
      {.xyxy = {{-0.5, 0.0, right, 0.0}}, .color = {0.3, 0.3, 0.3, 1.0}, .line_width_px = 1.2});
  return axes;
}

// Every shown group has enough seeds in trials.csv for box plots.
bool drawsBoxes(const std::vector<std::size_t>& shown, const std::vector<TrialRows>& trials) {
  return !shown.empty() && std::all_of(shown.begin(), shown.end(), [&](std::size_t g) {
    return g < trials.size() && static_cast<int>(trials[g].size()) >= kMinSeedsForBoxes;
  });
}

// The seeds of every row when they are equal, else 0.
int commonSeeds(const std::vector<std::size_t>& shown, const std::vector<TrialRows>& trials) {
  for (const std::size_t g : shown)
    if (trials[g].size() != trials[shown.front()].size()) return 0;
  return static_cast<int>(trials[shown.front()].size());
}

plot::Figure boxFigure(const std::vector<SummaryGroup>& groups,
                       const std::vector<std::size_t>& shown, const std::vector<TrialRows>& trials,
                       const std::string& left_out) {
  const auto methods = calibrationMethodsIn(groups);
  std::vector<const TrialRows*> rows;
  for (const std::size_t g : shown) rows.push_back(&trials[g]);
  std::vector<std::set<BoxKey>> off;
  int cols = 0;
  for (const PanelSpec& spec : panelSpecs()) {
    off.push_back(offScaleBoxes(rows, spec, methods));
    cols += off.back().empty() ? 1 : 2;
  }
  const int seeds = commonSeeds(shown, trials);
  std::string title = "Signed calibration error against the simulated truth";
  if (seeds > 0) title += " (" + boxSeedsNote(seeds) + ")";
  if (!left_out.empty()) title += "; every method refused: " + left_out;
  plot::Figure fig{.width_px = 530 * cols + 10,
                   .height_px = 70 + 330 * static_cast<int>(shown.size()),
                   .title = title,
                   .rows = static_cast<int>(shown.size()),
                   .cols = cols};
  for (const std::size_t g : shown) {
    const int n = static_cast<int>(trials[g].size());
    const std::string condition =
        conditionLabel(groups[g], groups) + (seeds > 0 ? "" : " (" + boxSeedsNote(n) + ")");
    for (std::size_t p = 0; p < panelSpecs().size(); ++p) {
      plot::Axes axes = boxPanel(trials[g], panelSpecs()[p], methods, off[p], false);
      if (p == 0) {
        axes.title = condition;  // the row's condition; the y label names the parameters
        if (g == shown.front()) axes.legend = plot::LegendPosition::Outside;
      }
      fig.axes.push_back(axes);
      if (!off[p].empty())
        fig.axes.push_back(boxPanel(trials[g], panelSpecs()[p], methods, off[p], true));
    }
  }
  return fig;
}

}  // namespace

plot::Figure calibrationFigure(const std::vector<SummaryGroup>& groups,
                               const std::vector<TrialRows>& trials_by_group) {
  const auto methods = calibrationMethodsIn(groups);
  // A condition where every method refused (an arc has no excitation to calibrate from) gets
  // no row; the title says so.
  std::vector<std::size_t> shown;
  std::string left_out;
  for (std::size_t k = 0; k < groups.size(); ++k) {
    bool any = false;
    for (const auto& method : methods)
      any = any || std::isfinite(statOf(
                       groups[k].metrics,
                       calibrationMetric(method, CalibrationError::kAbs, CalibrationParam::kB),
                       &MetricStats::mean));
    if (any)
      shown.push_back(k);
    else
      left_out += (left_out.empty() ? "" : ", ") + conditionLabel(groups[k], groups);
  }
  if (drawsBoxes(shown, trials_by_group))
    return boxFigure(groups, shown, trials_by_group, left_out);
  const int rows = std::max<int>(1, shown.size());
  // The seeds in the figure title when every group has as many, else in each row's title.
  const std::string common = commonSeedsNote(groups);
  std::string title = "Calibration error against the simulated truth";
  if (!common.empty()) title += " (" + common + ")";
  if (!left_out.empty()) title += "; every method refused: " + left_out;
  plot::Figure fig{
      .width_px = 1600, .height_px = 70 + 330 * rows, .title = title, .rows = rows, .cols = 3};
  for (const std::size_t k : shown) {
    const SummaryGroup& g = groups[k];
    const int seeds = seedsOf(g);
    const std::string condition =
        conditionLabel(g, groups) + (common.empty() ? " (" + seedsNote(seeds) + ")" : "");
    for (const PanelSpec& spec : panelSpecs()) {
      plot::Axes axes = calibrationPanel(g, spec, methods, seeds);
      if (&spec == &panelSpecs().front()) {
        axes.title = condition;  // the row's condition; the y label names the parameters
        if (k == shown.front())
          axes.legend = plot::LegendPosition::Outside;  // every method, beside the data
      }
      fig.axes.push_back(axes);
    }
  }
  return fig;
}

plot::Figure calibrationVsTimeFigure(const std::vector<SummaryGroup>& groups) {
  const std::vector<std::pair<CalibrationParam, std::string>> params = {
      {CalibrationParam::kB, "b |error| [%]"},
      {CalibrationParam::kRL, "r_{L} |error| [%]"},
      {CalibrationParam::kRR, "r_{R} |error| [%]"},
      {CalibrationParam::kMountYaw, "lidar yaw |error| [deg]"}};
  const auto methods = calibrationMethodsIn(groups);
  std::map<std::string, std::vector<const SummaryGroup*>, decltype(&naturalLess)> columns(
      naturalLess);
  for (const auto& g : groups) columns[otherSweepLabel(g, "duration_s")].push_back(&g);
  const auto duration = [](const SummaryGroup* g) { return std::stod(g->sweep.at("duration_s")); };
  for (auto& [_, members] : columns)  // along the driving time
    std::sort(members.begin(), members.end(), [&](const SummaryGroup* a, const SummaryGroup* b) {
      return duration(a) < duration(b);
    });
  const int cols = static_cast<int>(columns.size());
  plot::Figure fig{.width_px = 560 * cols + 200,
                   .height_px = 1300,
                   .title = "Calibration error vs driving time (" +
                            seedsNote(seedsOf(groups.front())) + " per point)",
                   .rows = static_cast<int>(params.size()),
                   .cols = cols};
  for (const auto& [param, label] : params)
    for (const auto& [column, members] : columns) {
      plot::Axes axes{.title = column,
                      .x_label = "driving time [s]",
                      .y_label = label,
                      .log_y = true,
                      .legend = plot::LegendPosition::None};
      if (&column == &columns.rbegin()->first && param == params.front().first)
        axes.legend = plot::LegendPosition::Outside;
      for (const std::string& method : methods) {
        plot::Series line = methodDots(calibrationPalette(), method);
        line.style = plot::Style::LineMarkers;
        for (const SummaryGroup* g : members) {
          const std::string path = calibrationMetric(method, CalibrationError::kAbs, param);
          pushMeanWithSpread(line, duration(g), g->metrics, path, seedsOf(*g));
        }
        if (std::any_of(line.y.begin(), line.y.end(), [](double v) { return std::isfinite(v); }))
          axes.series.push_back(line);
      }
      fig.axes.push_back(axes);
    }
  return fig;
}

}  // namespace slamprep::eval
