#pragma once
// The drawing steps render() composes, and what they share: data series and segments
// (draw_series.cpp), grid, frame, ticks and axis labels (draw_axes.cpp), the legend
// (draw_legend.cpp). Text is queued as TextItems and drawn after the geometry is read back.

#include <string>
#include <vector>

#include "slamprep/eval/plot/geometry.hpp"
#include "slamprep/eval/plot/gl_canvas.hpp"
#include "slamprep/eval/plot/layout.hpp"
#include "slamprep/eval/plot/plot.hpp"
#include "slamprep/eval/plot/text.hpp"

namespace slamprep::eval::plot {

inline constexpr Color kInk{0.13, 0.13, 0.13, 1.0};  ///< frame, ticks and text

/// A label to draw once the geometry has been read back.
struct TextItem {
  std::string text;
  double size = 0.0;
  double x = 0.0, y = 0.0;
  HAlign h = HAlign::Left;
  VAlign v = VAlign::Baseline;
  bool vertical = false;
};

/// A series' colour, marker and marker size after defaults.
struct Look {
  Color color;
  Marker marker = Marker::Circle;
  double marker_size = 8.0;
};

/// Colour, marker and marker size of every series of `axes`, in order.
std::vector<Look> resolveLooks(const Axes& axes);

inline PixelRect plotRect(const PanelLayout& L) {
  return {L.left_px, L.top_px, L.right_px, L.bottom_px};
}

/// The series' usable points in pixels, split where a point is unusable.
std::vector<std::vector<Vec2>> pixelRuns(const Axes& axes, std::size_t index, const PanelLayout& L);

/// Stroke of clipped polylines, dashed when asked.
Triangles strokeRuns(const std::vector<std::vector<Vec2>>& runs, const PixelRect& clip,
                     double width, bool dashed);

// ---- draw_series.cpp: inside the plot rectangle (the caller clips) ----

void drawSegments(GlCanvas& canvas, const Axes& axes, const PanelLayout& L);
/// Bars, error bars, line and markers of series `i`, as its style asks.
void drawSeries(GlCanvas& canvas, const Axes& axes, std::size_t i, const PanelLayout& L,
                const Look& look);

// ---- draw_axes.cpp ----

void drawGrid(GlCanvas& canvas, const PanelPlan& plan, const Axes& axes, const Metrics& m);
/// The frame and tick marks; queues the tick labels.
void drawFrameAndTicks(GlCanvas& canvas, const PanelPlan& plan, const Metrics& m,
                       std::vector<TextItem>& texts);
/// Queues the panel title and the axis labels.
void queueAxisLabels(const Axes& axes, const PanelPlan& plan, const Metrics& m, TextRenderer& text,
                     std::vector<TextItem>& texts);

// ---- draw_legend.cpp ----

/// The legend box in its corner (Auto: the corner hiding the least data); queues its labels.
void drawLegend(GlCanvas& canvas, const Axes& axes, const PanelLayout& L,
                const std::vector<Look>& looks, const Metrics& m, TextRenderer& text,
                std::vector<TextItem>& texts);

}  // namespace slamprep::eval::plot
