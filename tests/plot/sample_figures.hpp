#pragma once
// Synthetic figures shaped like the ones `slamprep plot` / `slamprep bench` draw; shared by the
// tests and written to <build>/plots/ by sample_figures_test so they can be looked at.

#include <cmath>
#include <numbers>
#include <vector>

#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot::samples {

/// De-skew error against angular rate, one line per method, log y.
inline Axes deskewAxes() {
  Axes axes{.title = "De-skew error vs angular rate",
            .x_label = "yaw rate ω [rad/s]",
            .y_label = "mean point error [m]",
            .log_y = true};
  std::vector<double> w;
  for (int i = 0; i <= 10; ++i) w.push_back(0.2 * i);
  const char* names[] = {"none", "linear odometry", "quadratic odometry", "odometry + ICP"};
  const double base[] = {2e-2, 1e-3, 4e-4, 1.5e-4};
  for (int m = 0; m < 4; ++m) {
    Series s{.label = names[m], .x = w, .style = Style::LineMarkers};
    for (const double wi : w) s.y.push_back(base[m] * (0.05 + wi * (1.0 + 0.3 * m * wi)));
    s.dashed = m == 0;
    axes.series.push_back(s);
  }
  return axes;
}

/// Calibration error per method and parameter with 1-sigma error bars (categorical x).
inline Axes calibrationAxes(Style style) {
  Axes axes{.title = "Calibration error per method",
            .y_label = "relative error [%]",
            .categories = {"direct linear", "model-based", "Censi 2013"}};
  const char* names[] = {"r_{L}", "r_{R}", "b"};
  const double err[3][3] = {{2.1, 0.6, 0.2}, {1.8, 0.5, 0.25}, {3.5, 1.1, 0.4}};
  const double sigma[3][3] = {{0.6, 0.2, 0.05}, {0.5, 0.15, 0.08}, {0.9, 0.3, 0.1}};
  for (int p = 0; p < 3; ++p) {
    Series s{.label = names[p], .x = {0, 1, 2}, .style = style};
    for (int m = 0; m < 3; ++m) s.y.push_back(err[m][p]), s.y_err.push_back(sigma[m][p]);
    axes.series.push_back(s);
  }
  return axes;
}

/// Signed calibration error of 40 seeds per method and parameter as box plots (categorical x):
/// one method biased, one wider, each with a few seeds far out.
inline Axes calibrationBoxAxes() {
  Axes axes{.title = "Signed calibration error, 40 seeds",
            .y_label = "error [%]",
            .legend = LegendPosition::Outside,
            .categories = {"r_{L}", "r_{R}", "b"}};
  const char* names[] = {"joint", "model", "ceres"};
  const double bias[] = {0.0, -0.16, 0.01}, spread[] = {0.03, 0.02, 0.05};
  axes.segments.push_back({.xyxy = {{-0.5, 0.0, 2.5, 0.0}}, .line_width_px = 1.2});
  for (int m = 0; m < 3; ++m) {
    Series s{.label = names[m], .style = Style::Box};
    for (int p = 0; p < 3; ++p)
      for (int k = 0; k < 40; ++k) {
        const double u = std::sin(12.9898 * (k + 40 * p + 120 * m)) * 43758.5453;
        const double z = 2.0 * (u - std::floor(u)) - 1.0;  // in [-1, 1), deterministic
        s.x.push_back(p);
        s.y.push_back(bias[m] + spread[m] * (k % 13 == 0 ? 4.0 * z : z));
      }
    axes.series.push_back(s);
  }
  return axes;
}

/// Ground truth vs nominal vs calibrated odometry, equal aspect.
inline Axes trajectoryAxes() {
  Axes axes{.title = "Trajectories", .x_label = "x [m]", .y_label = "y [m]", .equal_aspect = true};
  Series truth{.label = "ground truth", .color = Color{0, 0, 0, 1}, .line_width_px = 2.5};
  Series nominal{.label = "nominal odometry", .dashed = true};
  Series calibrated{.label = "calibrated odometry"};
  for (int i = 0; i <= 400; ++i) {
    const double t = 2.0 * std::numbers::pi * i / 400.0;
    const double x = 4.0 * std::sin(t), y = 2.0 * std::sin(2.0 * t);  // figure of eight
    truth.x.push_back(x), truth.y.push_back(y);
    nominal.x.push_back(x * 1.06 + 0.25 * t), nominal.y.push_back(y * 0.97 + 0.12 * t);
    calibrated.x.push_back(x + 0.02 * t), calibrated.y.push_back(y + 0.015 * t);
  }
  axes.series = {truth, nominal, calibrated};
  return axes;
}

/// One scan raw, de-skewed and true over the world outline, equal aspect.
inline Axes scanAxes() {
  Axes axes{.title = "Scan 17 (ω = 1.2 rad/s)",
            .x_label = "x [m]",
            .y_label = "y [m]",
            .equal_aspect = true};
  Segments world{.label = "world"};
  world.xyxy = {{-5, -3, 5, -3}, {5, -3, 5, 3}, {5, 3, -5, 3}, {-5, 3, -5, -3},
                {1, -1, 2, -1},  {2, -1, 2, 0}, {2, 0, 1, 0},  {1, 0, 1, -1}};
  axes.segments.push_back(world);
  Series truth{.label = "true", .style = Style::Points, .color = Color{0, 0, 0, 1}};
  Series raw{.label = "raw", .style = Style::Points, .color = rgb(0xD55E00)};
  Series fixed{.label = "de-skewed", .style = Style::Points, .color = rgb(0x0072B2)};
  for (int i = 0; i < 720; ++i) {
    const double a = -std::numbers::pi + 2.0 * std::numbers::pi * i / 720.0;
    const double c = std::cos(a), s = std::sin(a);
    const double r = std::min(std::abs(c) > 1e-9 ? 5.0 / std::abs(c) : 1e9,
                              std::abs(s) > 1e-9 ? 3.0 / std::abs(s) : 1e9);
    truth.x.push_back(r * c), truth.y.push_back(r * s);
    const double skew = 0.12 * i / 720.0;  // the robot turned while the beams were taken
    raw.x.push_back(r * std::cos(a + skew)), raw.y.push_back(r * std::sin(a + skew));
    fixed.x.push_back(r * std::cos(a + 0.004)), fixed.y.push_back(r * std::sin(a + 0.004));
  }
  axes.series = {truth, raw, fixed};
  return axes;
}

/// Calibration error against driving time.
inline Axes errorVsTimeAxes() {
  Axes axes{.title = "Calibration error vs driving time",
            .x_label = "driving time [s]",
            .y_label = "|b − b_{true}| [mm]",
            .log_x = true,
            .log_y = true};
  const char* names[] = {"direct linear", "model-based", "Censi 2013"};
  for (int m = 0; m < 3; ++m) {
    Series s{.label = names[m], .style = Style::LineMarkers};
    for (const double t : {10.0, 20.0, 50.0, 100.0, 200.0, 500.0, 1000.0}) {
      s.x.push_back(t);
      s.y.push_back((30.0 - 8.0 * m) / std::sqrt(t));
      s.y_err.push_back(0.3 * (30.0 - 8.0 * m) / std::sqrt(t));
    }
    axes.series.push_back(s);
  }
  return axes;
}

}  // namespace slamprep::eval::plot::samples
