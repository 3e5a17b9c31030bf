#include "eval/bench/figures.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <map>

#include "algo/deskew/deskew.hpp"
#include "core/atomic_file.hpp"
#include "core/paths.hpp"
#include "eval/bench/consistency_figure.hpp"
#include "eval/plot/plot.hpp"
#include "sim/physics/world.hpp"

namespace slamprep::eval {
namespace {

using nlohmann::json;
namespace fs = std::filesystem;

// Methods that appear under "<section>/<method>/<leaf>" in a metrics object, in key order.
std::vector<std::string> methodsWith(const json& metrics, const std::string& section,
                                     const std::string& leaf) {
  std::vector<std::string> out;
  for (const auto& [path, _] : metrics.items()) {
    const std::string prefix = section + "/";
    if (path.rfind(prefix, 0) != 0 || path.size() < leaf.size() + 1 ||
        path.compare(path.size() - leaf.size() - 1, std::string::npos, "/" + leaf) != 0)
      continue;
    const std::string method =
        path.substr(prefix.size(), path.find('/', prefix.size()) - prefix.size());
    if (out.empty() || out.back() != method) out.push_back(method);
  }
  return out;
}

double statOf(const json& metrics, const std::string& path, const char* stat) {
  return metrics.contains(path) ? metrics[path][stat].get<double>() : std::nan("");
}

// De-skew methods in the order of algo::allDeskewMethods() (none first, the floor), without the
// oracle: it sits at the rounding floor (~1e-12 mm) and would stretch a log axis over 10
// decades; the tables report it.
std::vector<std::string> plottedDeskewMethods(const json& metrics) {
  const auto present = methodsWith(metrics, "deskew", "mean_m");
  std::vector<std::string> out;
  for (const auto method : algo::allDeskewMethods()) {
    const std::string name(algo::deskewMethodName(method));
    if (method != algo::DeskewMethod::kOracle &&
        std::find(present.begin(), present.end(), name) != present.end())
      out.push_back(name);
  }
  return out;
}

constexpr int kMinSeedsForConsistency = 20;

constexpr const char* kOracleNote = "oracle (rounding floor, ~1e-12 mm) not drawn";

// Mean de-skew error per method over all trials, with 1-sigma bars; log y.
plot::Figure deskewByMethod(const json& metrics) {
  plot::Axes axes{.title = kOracleNote,
                  .y_label = "mean point error [mm]",
                  .log_y = true,
                  .legend = plot::LegendPosition::None};
  plot::Series bars{.style = plot::Style::Bars};
  for (const auto& m : plottedDeskewMethods(metrics)) {
    axes.categories.push_back(m);
    bars.x.push_back(axes.categories.size() - 1);
    bars.y.push_back(1e3 * statOf(metrics, "deskew/" + m + "/mean_m", "mean"));
    bars.y_err.push_back(1e3 * statOf(metrics, "deskew/" + m + "/mean_m", "std"));
  }
  axes.series.push_back(bars);
  return {.title =
              "De-skew error against the ground-truth undistorted points (mean ± 1σ over "
              "trials)",
          .axes = {axes}};
}

// The marker Auto would give the i-th series: fixed per method when panels show subsets.
plot::Marker methodMarker(std::size_t i) {
  static const plot::Marker kShapes[] = {plot::Marker::Circle,       plot::Marker::Square,
                                         plot::Marker::Triangle,     plot::Marker::Diamond,
                                         plot::Marker::TriangleDown, plot::Marker::Plus,
                                         plot::Marker::Cross};
  return kShapes[i % std::size(kShapes)];
}

// One method's line, y averaged over the groups that share an x (other sweep axes folded in),
// in the colour and marker of its place in the figure's method list, the same in every panel.
plot::Series meanLine(const std::string& method, std::size_t index,
                      const std::map<double, std::vector<double>>& points) {
  plot::Series s{.label = method,
                 .style = plot::Style::LineMarkers,
                 .color = plot::paletteColor(index),
                 .marker = methodMarker(index)};
  for (const auto& [x, values] : points) {
    double sum = 0.0;
    for (double v : values) sum += v;
    s.x.push_back(x);
    s.y.push_back(sum / values.size());
  }
  return s;
}

// "lidar.rate_hz=5, ...": the sweep values of a group, which separate the panels.
std::string sweepKey(const json& group) {
  std::string key;
  for (const auto& [axis, value] : group["sweep"].items())
    key += (key.empty() ? "" : ", ") + axis + "=" + value.get<std::string>();
  return key;
}

// "rate=5" before "rate=10": numbers inside the strings compare by value.
bool naturalLess(const std::string& a, const std::string& b) {
  std::size_t i = 0, j = 0;
  while (i < a.size() && j < b.size()) {
    if (std::isdigit(static_cast<unsigned char>(a[i])) &&
        std::isdigit(static_cast<unsigned char>(b[j]))) {
      char *end_a = nullptr, *end_b = nullptr;  // strtod: never throws, saturates
      const double x = std::strtod(a.c_str() + i, &end_a), y = std::strtod(b.c_str() + j, &end_b);
      if (x != y) return x < y;
      const std::size_t na = end_a - (a.c_str() + i), nb = end_b - (b.c_str() + j);
      i += na;
      j += nb;
    } else {
      if (a[i] != b[j]) return a[i] < b[j];
      ++i;
      ++j;
    }
  }
  return a.size() - i < b.size() - j;
}

// De-skew error against the mean angular rate of each scenario, one line per method; one panel
// per value of the other sweep axes (e.g. lidar rate), so they are not averaged together.
plot::Figure deskewVsRate(const json& groups) {
  std::map<std::string, std::vector<const json*>, decltype(&naturalLess)> panels(naturalLess);
  for (const auto& g : groups) panels[sweepKey(g)].push_back(&g);
  const int cols = std::min<int>(panels.size(), 3);
  const int rows = (static_cast<int>(panels.size()) + cols - 1) / cols;
  plot::Figure fig{.width_px = 700 * cols + 100,
                   .height_px = 650 * rows + 50,
                   .title = std::string("De-skew error vs angular rate (") + kOracleNote + ")",
                   .rows = rows,
                   .cols = cols};
  for (const auto& [key, members] : panels) {
    plot::Axes axes{.title = key,
                    .x_label = "mean |angular rate| [rad/s]",
                    .y_label = "mean point error [mm]",
                    .log_y = true};
    std::vector<std::string> methods;
    std::map<std::string, std::map<double, std::vector<double>>> by_method;
    for (const json* g : members) {
      const json& m = (*g)["metrics"];
      const double rate = statOf(m, "sim/mean_abs_yaw_rate_radps", "mean");
      methods = plottedDeskewMethods(m);
      for (const auto& method : methods)
        by_method[method][rate].push_back(1e3 * statOf(m, "deskew/" + method + "/mean_m", "mean"));
    }
    for (std::size_t i = 0; i < methods.size(); ++i) {
      auto series = meanLine(methods[i], i, by_method[methods[i]]);
      series.dashed = methods[i] == "odom-quadratic";  // lies on odom-linear at 100 Hz odometry
      axes.series.push_back(series);
    }
    fig.axes.push_back(axes);
  }
  return fig;
}

// Absolute calibration error per parameter, one bar per method, 1-sigma over trials.
plot::Figure calibrationByMethod(const json& metrics) {
  struct Panel {
    const char* title;
    const char* unit;
    std::vector<std::pair<std::string, std::string>> params;  // key, label
  };
  const std::vector<Panel> panels = {
      {"Wheel geometry",
       "|error| [%]",
       {{"r_L_pct", "r_{L}"}, {"r_R_pct", "r_{R}"}, {"b_pct", "b"}}},
      {"Lidar mount position", "|error| [mm]", {{"lidar_x_mm", "x"}, {"lidar_y_mm", "y"}}},
      {"Lidar mount yaw", "|error| [deg]", {{"lidar_yaw_deg", "yaw"}}}};
  plot::Figure fig{.width_px = 1500,
                   .height_px = 600,
                   .title = "Calibration error against the simulated truth (mean ± 1σ over trials)",
                   .rows = 1,
                   .cols = 3};
  const auto methods = methodsWith(metrics, "calibration", "ok");
  for (const auto& panel : panels) {
    plot::Axes axes{.title = panel.title, .y_label = panel.unit, .log_y = true};
    for (const auto& [_, label] : panel.params) axes.categories.push_back(label);
    for (std::size_t mi = 0; mi < methods.size(); ++mi) {
      plot::Series s{
          .label = methods[mi], .style = plot::Style::Bars, .color = plot::paletteColor(mi)};
      for (std::size_t i = 0; i < panel.params.size(); ++i) {
        const std::string path =
            "calibration/" + methods[mi] + "/abs_error/" + panel.params[i].first;
        s.x.push_back(i);
        s.y.push_back(statOf(metrics, path, "mean"));
        s.y_err.push_back(metrics.contains(path) ? statOf(metrics, path, "std") : 0.0);
      }
      axes.series.push_back(s);
    }
    fig.axes.push_back(axes);
  }
  return fig;
}

// Calibration error against driving time, averaged over the other sweep axes.
plot::Figure calibrationVsTime(const json& groups) {
  const std::vector<std::pair<std::string, std::string>> params = {
      {"b_pct", "b |error| [%]"},
      {"r_L_pct", "r_{L} |error| [%]"},
      {"r_R_pct", "r_{R} |error| [%]"},
      {"lidar_yaw_deg", "lidar yaw |error| [deg]"}};
  plot::Figure fig{.width_px = 1400,
                   .height_px = 1000,
                   .title =
                       "Calibration error vs driving time (mean over trials and the "
                       "other sweep axes)",
                   .rows = 2,
                   .cols = 2};
  // One colour per method in every panel, the same as in calibration_error.png.
  std::vector<std::string> methods;
  for (const auto& g : groups)
    for (const auto& method : methodsWith(g["metrics"], "calibration", "ok"))
      if (std::find(methods.begin(), methods.end(), method) == methods.end())
        methods.push_back(method);
  std::sort(methods.begin(), methods.end());
  for (const auto& [key, label] : params) {
    std::map<std::string, std::map<double, std::vector<double>>> by_method;
    for (const auto& g : groups) {
      const json& m = g["metrics"];
      const double t = statOf(m, "sim/duration_s", "mean");
      for (const auto& method : methodsWith(m, "calibration", "ok")) {
        const double v = statOf(m, "calibration/" + method + "/abs_error/" + key, "mean");
        if (std::isfinite(v)) by_method[method][t].push_back(v);
      }
    }
    plot::Axes axes{.x_label = "driving time [s]", .y_label = label, .log_y = true};
    for (std::size_t i = 0; i < methods.size(); ++i)
      if (const auto it = by_method.find(methods[i]); it != by_method.end())
        axes.series.push_back(meanLine(methods[i], i, it->second));
    fig.axes.push_back(axes);
  }
  return fig;
}

plot::Segments worldOutline(const Suite& suite) {
  plot::Segments seg{.label = "world", .color = {0.55, 0.55, 0.55, 1.0}, .line_width_px = 1.5};
  const sim::World world = sim::loadWorld(resolveDataPath(suite.worlds.front()));
  for (const auto& poly : sim::outline(world))
    for (std::size_t i = 0; i < poly.size(); ++i) {
      const auto& a = poly[i];
      const auto& b = poly[(i + 1) % poly.size()];
      seg.xyxy.push_back({a.x(), a.y(), b.x(), b.y()});
    }
  return seg;
}

plot::Series xySeries(const json& points, std::string label, plot::Style style) {
  plot::Series s{.label = std::move(label), .style = style};
  for (const auto& p : points) {
    s.x.push_back(p[0].get<double>());
    s.y.push_back(p[1].get<double>());
  }
  return s;
}

plot::Figure trajectoryFigure(const Suite& suite, const json& trajectory) {
  plot::Axes axes{.x_label = "x [m]", .y_label = "y [m]", .equal_aspect = true};
  axes.segments.push_back(worldOutline(suite));
  // Truth wide and light underneath: calibrated odometry lies on it and must not hide it.
  plot::Series truth = xySeries(trajectory["true"], "ground truth", plot::Style::Line);
  truth.color = plot::rgb(0x999999);
  truth.line_width_px = 6.0;
  axes.series.push_back(truth);
  axes.series.push_back(
      xySeries(trajectory["nominal"], "odometry, nominal geometry", plot::Style::Line));
  if (trajectory.contains("calibrated"))
    axes.series.push_back(xySeries(
        trajectory["calibrated"],
        "odometry, calibrated geometry (" + trajectory.value("calibrated_method", "?") + ")",
        plot::Style::Line));
  axes.series[1].dashed = true;
  return {.width_px = 1200,
          .height_px = 1000,
          .title = "Trajectory: truth vs dead reckoning (first trial)",
          .axes = {axes}};
}

plot::Figure scanFigure(const Suite& suite, const json& scan) {
  plot::Axes axes{.x_label = "x [m]", .y_label = "y [m]", .equal_aspect = true};
  axes.segments.push_back(worldOutline(suite));
  // Truth underneath and larger, so corrected points sitting on it stay visible.
  plot::Series truth = xySeries(scan["true"], "ground truth", plot::Style::Points);
  truth.color = plot::rgb(0x999999);
  truth.marker_size_px = 6.0;
  axes.series.push_back(truth);
  axes.series.push_back(xySeries(scan["raw"], "raw (distorted)", plot::Style::Points));
  if (scan.contains("deskewed"))
    axes.series.push_back(xySeries(scan["deskewed"],
                                   "de-skewed (" + scan["deskew_method"].get<std::string>() + ")",
                                   plot::Style::Points));
  for (std::size_t i = 1; i < axes.series.size(); ++i) axes.series[i].marker_size_px = 3.0;
  plot::Series lidar{.label = "lidar", .style = plot::Style::Markers, .marker_size_px = 12.0};
  lidar.x = {scan["lidar"][0].get<double>()};
  lidar.y = {scan["lidar"][1].get<double>()};
  axes.series.push_back(lidar);
  return {.width_px = 1200,
          .height_px = 1000,
          .title = "The most distorted scan of the first trial, in the world frame",
          .axes = {axes}};
}

// The first trial's artifacts (trajectories, one scan), if recorded.
std::optional<json> firstArtifacts(const Suite& suite, const fs::path& out_dir) {
  const auto trials = expandTrials(suite);
  const auto file = out_dir / "trials" / (trials.front().id + ".json");
  if (!fs::exists(file)) return std::nullopt;
  json trial = json::parse(readFile(file));
  if (!trial.contains("artifacts")) return std::nullopt;
  return trial["artifacts"];
}

}  // namespace

std::vector<std::string> renderSuitePlots(const Suite& suite, const json& summary,
                                          const fs::path& out_dir) {
  std::vector<std::pair<std::string, plot::Figure>> figures;
  const json& metrics = summary["metrics"];
  const json& groups = summary["groups"];
  if (!methodsWith(metrics, "deskew", "mean_m").empty()) {
    figures.emplace_back("deskew_by_method.png", deskewByMethod(metrics));
    if (groups.size() >= 3) figures.emplace_back("deskew_vs_rate.png", deskewVsRate(groups));
  }
  if (!methodsWith(metrics, "calibration", "ok").empty()) {
    figures.emplace_back("calibration_error.png", calibrationByMethod(metrics));
    // Only where driving time is what the suite varies; scenarios of different lengths are not.
    const bool sweeps_time = std::any_of(suite.sweep.begin(), suite.sweep.end(),
                                         [](const SweepAxis& a) { return a.key == "duration_s"; });
    if (sweeps_time) figures.emplace_back("calibration_vs_time.png", calibrationVsTime(groups));
  }
  // error/sigma histograms need many seeds of one experiment to say anything (the seeds suite).
  if (suite.seeds >= kMinSeedsForConsistency)
    if (auto fig = consistencyFigure(readTrialRows(out_dir / "trials.csv")))
      figures.emplace_back("consistency.png", std::move(*fig));
  if (const auto artifacts = firstArtifacts(suite, out_dir)) {
    if (artifacts->contains("trajectory"))
      figures.emplace_back("trajectory.png", trajectoryFigure(suite, (*artifacts)["trajectory"]));
    if (artifacts->contains("scan"))
      figures.emplace_back("scan.png", scanFigure(suite, (*artifacts)["scan"]));
  }
  std::vector<std::string> written;
  fs::create_directories(out_dir / "plots");
  for (const auto& [name, figure] : figures) {
    plot::renderPng(figure, out_dir / "plots" / name);
    written.push_back(name);
  }
  return written;
}

}  // namespace slamprep::eval
