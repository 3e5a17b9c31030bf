#include <algorithm>
#include <cmath>

#include "slamprep/core/paths.hpp"
#include "slamprep/eval/bench/figures_internal.hpp"
#include "slamprep/sim/physics/world.hpp"

namespace slamprep::eval {
namespace {

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

plot::Series xySeries(const WorldPoints& points, std::string label, plot::Style style) {
  plot::Series s{.label = std::move(label), .style = style};
  for (const auto& p : points) {
    s.x.push_back(p[0]);
    s.y.push_back(p[1]);
  }
  return s;
}

plot::Series mark(const std::array<double, 2>& point, std::string label, plot::Marker marker) {
  return {.label = std::move(label),
          .x = {point[0]},
          .y = {point[1]},
          .style = plot::Style::Markers,
          .color = plot::rgb(0x000000),
          .marker_size_px = 14.0,
          .marker = marker};
}

// Distance of each beam's point to its true point, in mm (both lists hold the same beams).
plot::Series residualsMm(const WorldPoints& points, const WorldPoints& truth, std::string label,
                         plot::Color color) {
  plot::Series s{.label = std::move(label),
                 .style = plot::Style::Points,
                 .color = color,
                 .marker_size_px = 3.0};
  for (std::size_t i = 0; i < points.size(); ++i) {
    s.x.push_back(static_cast<double>(i));
    s.y.push_back(1e3 * std::hypot(points[i][0] - truth[i][0], points[i][1] - truth[i][1]));
  }
  return s;
}

}  // namespace

plot::Figure trajectoryFigure(const Suite& suite, const TrajectoriesRecord& trajectory) {
  plot::Axes axes{.x_label = "x [m]",
                  .y_label = "y [m]",
                  .equal_aspect = true,
                  .legend = plot::LegendPosition::Outside};
  axes.segments.push_back(worldOutline(suite));
  // Truth wide and light underneath: calibrated odometry lies on it and must not hide it.
  plot::Series truth = xySeries(trajectory.truth, "ground truth", plot::Style::Line);
  truth.color = plot::rgb(0x999999);
  truth.line_width_px = 6.0;
  axes.series.push_back(truth);
  plot::Series nominal =
      xySeries(trajectory.nominal, "odometry, nominal geometry", plot::Style::Line);
  nominal.dashed = true;
  axes.series.push_back(nominal);
  if (trajectory.calibrated) {
    const std::string& method = trajectory.calibrated_method;
    axes.series.push_back(xySeries(*trajectory.calibrated,
                                   "odometry, calibrated (" + (method.empty() ? "?" : method) + ")",
                                   plot::Style::Line));
  }
  const WorldPoints& path = trajectory.truth;
  axes.series.push_back(mark(path.front(), "start", plot::Marker::Circle));
  axes.series.push_back(mark(path.back(), "end (truth)", plot::Marker::Square));
  return {.width_px = 1400,
          .height_px = 1000,
          .title = "Trajectory: truth vs dead reckoning (first trial)",
          .axes = {axes}};
}

plot::Figure scanFigure(const Suite& suite, const ArtifactScanRecord& scan) {
  plot::Axes axes{.x_label = "x [m]",
                  .y_label = "y [m]",
                  .equal_aspect = true,
                  .legend = plot::LegendPosition::Outside};
  axes.segments.push_back(worldOutline(suite));
  // Truth underneath and larger, so corrected points sitting on it stay visible.
  plot::Series truth = xySeries(scan.truth, "ground truth", plot::Style::Points);
  truth.color = plot::rgb(0x999999);
  truth.marker_size_px = 6.0;
  axes.series.push_back(truth);
  axes.series.push_back(xySeries(scan.raw, "raw (distorted)", plot::Style::Points));
  const std::string& method = scan.deskew_method;
  if (scan.deskewed)
    axes.series.push_back(
        xySeries(*scan.deskewed, "de-skewed (" + method + ")", plot::Style::Points));
  for (std::size_t i = 1; i < axes.series.size(); ++i) axes.series[i].marker_size_px = 3.0;
  plot::Series lidar{.label = "lidar", .style = plot::Style::Markers, .marker_size_px = 12.0};
  lidar.x = {scan.lidar[0]};
  lidar.y = {scan.lidar[1]};
  axes.series.push_back(lidar);
  plot::Figure fig{.width_px = 1400,
                   .height_px = 1300,
                   .title = "The most distorted scan of the first trial, in the world frame",
                   .rows = 2,
                   .cols = 1,
                   .axes = {axes}};
  // Millimetres are invisible at room scale: each beam's distance to its true point below.
  if (scan.raw.size() == scan.truth.size()) {
    plot::Axes residual{.title = "distance of each beam's point to its true point",
                        .x_label = "beam (in the order taken)",
                        .y_label = "error [mm]",
                        .log_y = true,
                        // The reference beam is exact to rounding: keep the axis on what shows.
                        .y_range = plot::Range{1e-3, 1e4},
                        .legend = plot::LegendPosition::Outside};
    residual.series.push_back(residualsMm(scan.raw, scan.truth, "raw", plot::paletteColor(0)));
    if (scan.deskewed && scan.deskewed->size() == scan.truth.size())
      residual.series.push_back(residualsMm(*scan.deskewed, scan.truth,
                                            "de-skewed (" + method + ")", plot::paletteColor(1)));
    fig.axes.push_back(residual);
  }
  fig.rows = static_cast<int>(fig.axes.size());
  if (fig.rows == 1) fig.height_px = 1000;
  return fig;
}

plot::Figure odometryErrorFigure(const OdometryErrorRecord& odometry_error) {
  // Log y: calibrated odometry errs by millimetres where nominal errs by metres; on a linear
  // axis its line lies flat on zero. Hence also |heading error| (a log axis holds no sign).
  plot::Axes trans{.title = "Position error",
                   .x_label = "time [s]",
                   .y_label = "|position error| [m]",
                   .log_y = true,
                   .legend = plot::LegendPosition::Outside};
  plot::Axes heading{.title = "Heading error",
                     .x_label = "time [s]",
                     .y_label = "|heading error| [deg]",
                     .log_y = true,
                     .legend = plot::LegendPosition::Outside};
  std::size_t i = 0;
  for (const auto& [name, series] :
       {std::pair{"nominal", &odometry_error.nominal},
        std::pair{"calibrated",
                  odometry_error.calibrated ? &*odometry_error.calibrated : nullptr}}) {
    if (!series) continue;
    const OdometryErrorSeries& e = *series;
    const std::string label = std::string(name) + " geometry";
    plot::Series t{.label = label, .color = plot::paletteColor(i)};
    plot::Series h{.label = label, .color = plot::paletteColor(i)};
    t.dashed = h.dashed = i == 0;
    const std::size_t n = std::min({e.t.size(), e.translation_m.size(), e.heading_deg.size()});
    for (std::size_t k = 0; k < n; ++k) {
      t.x.push_back(e.t[k]);
      t.y.push_back(e.translation_m[k]);
      h.x.push_back(e.t[k]);
      h.y.push_back(std::abs(e.heading_deg[k]));
    }
    trans.series.push_back(t);
    heading.series.push_back(h);
    ++i;
  }
  return {.width_px = 1300,
          .height_px = 900,
          .title =
              "Dead-reckoning error against the truth, started on the true pose (first "
              "trial, 1 seed; log scale)",
          .rows = 2,
          .cols = 1,
          .axes = {trans, heading}};
}

}  // namespace slamprep::eval
