#include <algorithm>
#include <cmath>
#include <map>

#include "slamprep/eval/plot/draw.hpp"

namespace slamprep::eval::plot {
namespace {

constexpr Marker kMarkerCycle[] = {Marker::Circle, Marker::Square, Marker::Triangle,
                                   Marker::Diamond, Marker::TriangleDown};

void drawBars(GlCanvas& canvas, const Axes& axes, std::size_t i, const PanelLayout& L,
              const Look& look) {
  const Series& s = axes.series[i];
  const double offset = dodgeOffset(axes, i), half = barWidth(axes, i) / 2;
  const double base = axes.log_y ? L.bottom_px : L.toPixelY(0.0);
  const PixelRect clip = plotRect(L).grown(2.0);
  Triangles bars;
  for (std::size_t k = 0; k < s.x.size(); ++k) {
    const double x = s.x[k] + offset;
    if (!usable(x - half, axes.log_x) || !usable(x + half, axes.log_x) ||
        !usable(s.y[k], axes.log_y)) {
      continue;
    }
    const double y = L.toPixelY(s.y[k]);
    PixelRect r{L.toPixelX(x - half), std::min(y, base), L.toPixelX(x + half), std::max(y, base)};
    r = {std::max(r.left, clip.left), std::max(r.top, clip.top), std::min(r.right, clip.right),
         std::min(r.bottom, clip.bottom)};
    if (r.left < r.right && r.top < r.bottom) appendRect(bars, r);
  }
  canvas.fill(bars, look.color, false);
}

// The sample of every distinct usable x of a Box series, in ascending x.
std::map<double, std::vector<double>> boxSamples(const Axes& axes, const Series& s) {
  std::map<double, std::vector<double>> samples;
  for (std::size_t k = 0; k < s.x.size(); ++k)
    if (usable(s.x[k], axes.log_x) && usable(s.y[k], axes.log_y)) samples[s.x[k]].push_back(s.y[k]);
  return samples;
}

// Box (quartiles, translucent fill and outline), median line, whiskers with caps, outliers.
void drawBoxes(GlCanvas& canvas, const Axes& axes, std::size_t i, const PanelLayout& L,
               const Look& look) {
  const Series& s = axes.series[i];
  const double offset = dodgeOffset(axes, i), half = barWidth(axes, i) / 2;
  const double width = std::max(1.0, 0.75 * s.line_width_px);
  Triangles fill, outline, dots;
  std::vector<std::vector<Vec2>> whiskers, medians;
  for (const auto& [x, sample] : boxSamples(axes, s)) {
    const double cx = x + offset;
    if (!usable(cx - half, axes.log_x) || !usable(cx + half, axes.log_x)) continue;
    const BoxStats b = boxStats(sample);
    const double left = L.toPixelX(cx - half), right = L.toPixelX(cx + half);
    const double mid = L.toPixelX(cx), cap = (right - left) / 4;
    const PixelRect box{left, L.toPixelY(b.q3), right, L.toPixelY(b.q1)};
    appendRect(fill, box);
    appendRectOutline(outline, box, width);
    using Whisker = std::pair<double, double>;  // from the box edge to the tip
    for (const auto& [edge, tip] : {Whisker{b.q3, b.whisker_high}, Whisker{b.q1, b.whisker_low}}) {
      if (tip == edge) continue;
      whiskers.push_back({{mid, L.toPixelY(edge)}, {mid, L.toPixelY(tip)}});
      whiskers.push_back({{mid - cap, L.toPixelY(tip)}, {mid + cap, L.toPixelY(tip)}});
    }
    medians.push_back({{left, L.toPixelY(b.median)}, {right, L.toPixelY(b.median)}});
    for (const double v : b.outliers) appendDisc(dots, {mid, L.toPixelY(v)}, look.marker_size / 2);
  }
  const PixelRect clip = plotRect(L).grown(2 * width);
  canvas.fill(fill, {look.color.r, look.color.g, look.color.b, 0.3 * look.color.a}, false);
  canvas.fill(outline, look.color, false);
  canvas.fill(strokeRuns(whiskers, clip, width, false), look.color);
  canvas.fill(strokeRuns(medians, clip, 2 * width, false), kInk);
  canvas.fill(dots, look.color, false);
}

void drawErrorBars(GlCanvas& canvas, const Axes& axes, std::size_t i, const PanelLayout& L,
                   const Look& look) {
  const Series& s = axes.series[i];
  if (s.y_err.empty()) return;
  const bool bars = s.style == Style::Bars;
  const double width = std::max(1.0, 0.75 * s.line_width_px);
  const double offset = dodgeOffset(axes, i);
  double cap = std::max(3.0, 0.6 * look.marker_size);
  if (bars) {
    const double bar_px = L.toPixelX(offset + barWidth(axes, i)) - L.toPixelX(offset);
    cap = std::clamp(0.2 * std::abs(bar_px), 3.0, 10.0);
  }
  const PixelRect clip = plotRect(L).grown(width * 2);
  std::vector<std::vector<Vec2>> runs;
  for (std::size_t k = 0; k < s.x.size(); ++k) {
    const double x = s.x[k] + offset, y = s.y[k], e = std::abs(s.y_err[k]);
    const double e_low = s.y_err_low.empty() ? e : std::abs(s.y_err_low[k]);
    if (!usable(x, axes.log_x) || !usable(y, axes.log_y) || !std::isfinite(e) ||
        !std::isfinite(e_low) || (e == 0.0 && e_low == 0.0))
      continue;
    const double px = L.toPixelX(x);
    const double top = L.toPixelY(y + e);
    const bool low_ok = usable(y - e_low, axes.log_y);
    const double bottom = low_ok ? L.toPixelY(y - e_low) : L.bottom_px + 2.0 * width;
    if (!usable(y + e, axes.log_y)) continue;
    runs.push_back({{px, top}, {px, bottom}});
    runs.push_back({{px - cap, top}, {px + cap, top}});
    if (low_ok) runs.push_back({{px - cap, bottom}, {px + cap, bottom}});
  }
  canvas.fill(strokeRuns(runs, clip, width, false), bars ? kInk : look.color);
}

void drawMarkers(GlCanvas& canvas, const std::vector<std::vector<Vec2>>& runs, const Look& look,
                 Style style, double line_width, const PixelRect& plot) {
  const PixelRect keep = plot.grown(look.marker_size);
  Triangles markers;
  for (const auto& run : runs) {
    for (const Vec2& p : run) {
      if (!keep.contains(p)) continue;
      if (style == Style::Points) {
        appendDisc(markers, p, look.marker_size / 2);
      } else {
        appendMarker(markers, look.marker, p, look.marker_size, std::max(1.5, line_width));
      }
    }
  }
  canvas.fill(markers, look.color, false);
}

}  // namespace

std::vector<Look> resolveLooks(const Axes& axes) {
  std::vector<Look> looks;
  std::size_t automatic = 0;  // palette slot of the next series without a colour
  for (std::size_t i = 0; i < axes.series.size(); ++i) {
    const Series& s = axes.series[i];
    Look look;
    look.color = s.color ? *s.color : paletteColor(automatic++);
    look.marker = s.marker != Marker::Auto ? s.marker : kMarkerCycle[i % std::size(kMarkerCycle)];
    const double size = s.style == Style::Points ? 3.0 : s.style == Style::Box ? 4.0 : 8.0;
    look.marker_size = s.marker_size_px.value_or(size);
    looks.push_back(look);
  }
  return looks;
}

/// The series' usable points in pixels, split where a point is unusable.
std::vector<std::vector<Vec2>> pixelRuns(const Axes& axes, std::size_t index,
                                         const PanelLayout& L) {
  const Series& s = axes.series[index];
  const double offset = dodgeOffset(axes, index);
  std::vector<std::vector<Vec2>> runs(1);
  for (std::size_t k = 0; k < s.x.size(); ++k) {
    const double x = s.x[k] + offset;
    if (usable(x, axes.log_x) && usable(s.y[k], axes.log_y)) {
      runs.back().push_back({L.toPixelX(x), L.toPixelY(s.y[k])});
    } else if (!runs.back().empty()) {
      runs.emplace_back();
    }
  }
  if (runs.back().empty()) runs.pop_back();
  return runs;
}

/// Stroke of clipped polylines, dashed when asked.
Triangles strokeRuns(const std::vector<std::vector<Vec2>>& runs, const PixelRect& clip,
                     double width, bool dashed) {
  Triangles out;
  for (const auto& run : runs) {
    for (const auto& part : clipPolyline(run, clip)) {
      if (!dashed) {
        appendStroke(out, part, width);
        continue;
      }
      const auto [on, off] = dashPattern(width);
      for (const auto& dash : dashPolyline(part, on, off)) appendStroke(out, dash, width);
    }
  }
  return out;
}

void drawSegments(GlCanvas& canvas, const Axes& axes, const PanelLayout& L) {
  for (const Segments& segments : axes.segments) {
    std::vector<std::vector<Vec2>> runs;
    for (const auto& [x0, y0, x1, y1] : segments.xyxy) {
      if (!usable(x0, axes.log_x) || !usable(y0, axes.log_y) || !usable(x1, axes.log_x) ||
          !usable(y1, axes.log_y)) {
        continue;
      }
      runs.push_back({{L.toPixelX(x0), L.toPixelY(y0)}, {L.toPixelX(x1), L.toPixelY(y1)}});
    }
    const PixelRect clip = plotRect(L).grown(segments.line_width_px * 2);
    canvas.fill(strokeRuns(runs, clip, segments.line_width_px, segments.dashed), segments.color);
  }
}

void drawSeries(GlCanvas& canvas, const Axes& axes, std::size_t i, const PanelLayout& L,
                const Look& look) {
  const Series& s = axes.series[i];
  if (s.style == Style::Box) return drawBoxes(canvas, axes, i, L, look);
  if (s.style == Style::Bars) drawBars(canvas, axes, i, L, look);
  drawErrorBars(canvas, axes, i, L, look);
  const auto runs = pixelRuns(axes, i, L);
  if (s.style == Style::Line || s.style == Style::LineMarkers) {
    const PixelRect clip = plotRect(L).grown(s.line_width_px * 2);
    canvas.fill(strokeRuns(runs, clip, s.line_width_px, s.dashed), look.color);
  }
  if (s.style == Style::Markers || s.style == Style::LineMarkers || s.style == Style::Points) {
    drawMarkers(canvas, runs, look, s.style, s.line_width_px, plotRect(L));
  }
}

}  // namespace slamprep::eval::plot
