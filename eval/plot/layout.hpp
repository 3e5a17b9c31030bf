#pragma once
// Figure layout: validation, data ranges (auto margins, equal aspect), ticks, and the plot
// rectangle of every panel, sized so that no label is clipped.

#include <vector>

#include "slamprep/eval/plot/geometry.hpp"
#include "slamprep/eval/plot/plot.hpp"
#include "slamprep/eval/plot/text.hpp"
#include "slamprep/eval/plot/ticks.hpp"

namespace slamprep::eval::plot {

/// Font sizes and spacing in pixels, scaled by Figure::font_scale.
struct Metrics {
  double tick_font = 14.0;          ///< tick labels
  double label_font = 16.0;         ///< axis labels
  double title_font = 17.0;         ///< panel titles
  double figure_title_font = 20.0;  ///< figure title
  double legend_font = 14.0;        ///< legend entries
  double pad = 8.0;                 ///< generic gap
  double tick_length = 5.0;         ///< major tick length (minor: 3/5 of it)
  double line = 1.0;                ///< frame, tick and grid line width
};

Metrics metricsFor(const Figure& figure);

/// Throws InputError naming the offending field when the figure cannot be drawn.
void validateFigure(const Figure& figure);

/// A panel with its cell, final plot rectangle and ranges, and its ticks.
struct PanelPlan {
  PixelRect cell;
  PanelLayout layout;
  std::vector<Tick> x_ticks;
  std::vector<Tick> y_ticks;
};

struct FigurePlan {
  Metrics metrics;
  double title_center_y = 0.0;  ///< vertical centre of the figure title
  std::vector<PanelPlan> panels;
};

/// Width of a LegendPosition::Outside legend (0 without labelled series), which the panel's
/// plot area leaves free on its right (draw_legend.cpp).
double outsideLegendWidth(const Axes& axes, const Metrics& m, TextRenderer& text);

/// Lays out every panel of a validated figure.
FigurePlan planFigure(const Figure& figure, TextRenderer& text);

/// Whether a data value can be placed on an axis (finite, and positive on a log axis).
bool usable(double value, bool log_axis);

/// Horizontal offset of series `index` on a categorical axis (side by side within a slot).
double dodgeOffset(const Axes& axes, std::size_t index);
/// Bar width in x units for series `index` of `axes`.
double barWidth(const Axes& axes, std::size_t index);

}  // namespace slamprep::eval::plot
