#include <algorithm>
#include <cmath>
#include <limits>

#include "slamprep/eval/plot/draw.hpp"

namespace slamprep::eval::plot {
namespace {

const Color kLegendFill{1.0, 1.0, 1.0, 0.88};    ///< legend background
const Color kLegendEdge{0.80, 0.80, 0.80, 1.0};  ///< legend border

struct LegendEntry {
  std::string label;
  const Series* series = nullptr;      ///< or
  const Segments* segments = nullptr;  ///< one of the two
  Look look;
};

std::vector<LegendEntry> legendEntries(const Axes& axes, const std::vector<Look>& looks) {
  std::vector<LegendEntry> entries;
  for (const Segments& s : axes.segments) {
    if (!s.label.empty()) entries.push_back({s.label, nullptr, &s, {s.color}});
  }
  for (std::size_t i = 0; i < axes.series.size(); ++i) {
    const Series& s = axes.series[i];
    if (!s.label.empty()) entries.push_back({s.label, &s, nullptr, looks[i]});
  }
  return entries;
}

/// How much of the data a box would hide: points inside plus half the stroke length inside.
double coverage(const Axes& axes, const PanelLayout& L, const PixelRect& box) {
  double covered = 0.0;
  auto strokeInside = [&](Vec2 a, Vec2 b) {
    if (clipSegment(a, b, box)) covered += 0.5 * std::hypot(b.x - a.x, b.y - a.y);
  };
  for (std::size_t i = 0; i < axes.series.size(); ++i) {
    const Style style = axes.series[i].style;
    for (const auto& run : pixelRuns(axes, i, L)) {
      for (std::size_t k = 0; k < run.size(); ++k) {
        if (box.contains(run[k])) covered += style == Style::Bars ? 20.0 : 1.0;
        if (k > 0 && (style == Style::Line || style == Style::LineMarkers)) {
          strokeInside(run[k - 1], run[k]);
        }
        if (style == Style::Bars) {  // the bar body, from the base to the point
          const double base = axes.log_y ? L.bottom_px : L.toPixelY(0.0);
          strokeInside(run[k], {run[k].x, base});
        }
      }
    }
  }
  for (const Segments& s : axes.segments) {
    for (const auto& [x0, y0, x1, y1] : s.xyxy) {
      if (usable(x0, axes.log_x) && usable(y0, axes.log_y) && usable(x1, axes.log_x) &&
          usable(y1, axes.log_y)) {
        strokeInside({L.toPixelX(x0), L.toPixelY(y0)}, {L.toPixelX(x1), L.toPixelY(y1)});
      }
    }
  }
  return covered;
}

PixelRect legendBox(LegendPosition position, const PanelLayout& L, double w, double h,
                    double inset) {
  const bool right =
      position == LegendPosition::UpperRight || position == LegendPosition::LowerRight;
  const bool lower =
      position == LegendPosition::LowerLeft || position == LegendPosition::LowerRight;
  const double left = right ? L.right_px - inset - w : L.left_px + inset;
  const double top = lower ? L.bottom_px - inset - h : L.top_px + inset;
  return {std::round(left), std::round(top), std::round(left + w), std::round(top + h)};
}

void drawLegendSample(GlCanvas& canvas, const LegendEntry& e, double x0, double x1, double y) {
  Triangles shape;
  const double mid = (x0 + x1) / 2;
  if (e.segments) {
    const std::vector<std::vector<Vec2>> line{{{x0, y}, {x1, y}}};
    const PixelRect any{x0 - 10, y - 10, x1 + 10, y + 10};
    canvas.fill(strokeRuns(line, any, e.segments->line_width_px, e.segments->dashed), e.look.color);
    return;
  }
  const Series& s = *e.series;
  if (s.style == Style::Line || s.style == Style::LineMarkers) {
    const std::vector<std::vector<Vec2>> line{{{x0, y}, {x1, y}}};
    const PixelRect any{x0 - 10, y - 10, x1 + 10, y + 10};
    canvas.fill(strokeRuns(line, any, s.line_width_px, s.dashed), e.look.color);
  }
  if (s.style == Style::Markers || s.style == Style::LineMarkers) {
    appendMarker(shape, e.look.marker, {mid, y}, e.look.marker_size,
                 std::max(1.5, s.line_width_px));
  } else if (s.style == Style::Points) {
    const double r = std::max(2.0, e.look.marker_size / 2);
    for (const double f : {0.2, 0.5, 0.8}) appendDisc(shape, {x0 + f * (x1 - x0), y}, r);
  } else if (s.style == Style::Bars) {
    const double half = 0.35 * (x1 - x0) / 2 + 3.0;
    appendRect(shape, {mid - half, y - half * 0.8, mid + half, y + half * 0.8});
  } else if (s.style == Style::Box) {  // a small box with its median line
    const double half = 0.35 * (x1 - x0) / 2 + 3.0;
    const PixelRect box{mid - half, y - half * 0.8, mid + half, y + half * 0.8};
    Triangles fill, median;
    appendRect(fill, box);
    const Color c = e.look.color;
    canvas.fill(fill, {c.r, c.g, c.b, 0.3 * c.a}, false);
    appendRectOutline(shape, box, std::max(1.0, 0.75 * s.line_width_px));
    appendStroke(median, {{box.left, y}, {box.right, y}}, 1.5 * s.line_width_px);
    canvas.fill(median, kInk, false);
  }
  canvas.fill(shape, e.look.color, false);
}

}  // namespace

double outsideLegendWidth(const Axes& axes, const Metrics& m, TextRenderer& text) {
  double widest = 0.0;
  bool any = false;
  for (const Segments& s : axes.segments)
    if (!s.label.empty())
      widest = std::max(widest, text.measure(s.label, m.legend_font).width_px), any = true;
  for (const Series& s : axes.series)
    if (!s.label.empty())
      widest = std::max(widest, text.measure(s.label, m.legend_font).width_px), any = true;
  return any ? m.pad + 2.4 * m.legend_font + m.pad + widest + m.pad * 1.25 : 0.0;
}

void drawLegend(GlCanvas& canvas, const Axes& axes, const PanelLayout& L,
                const std::vector<Look>& looks, const Metrics& m, TextRenderer& text,
                std::vector<TextItem>& texts) {
  if (axes.legend == LegendPosition::None) return;
  const auto entries = legendEntries(axes, looks);
  if (entries.empty()) return;
  const double row = 1.5 * m.legend_font;
  const double sample = 2.4 * m.legend_font;
  const double w = outsideLegendWidth(axes, m, text);
  const double h = m.pad * 0.75 * 2 + row * static_cast<double>(entries.size());

  LegendPosition position = axes.legend;
  if (position == LegendPosition::Auto) {
    double best = std::numeric_limits<double>::infinity();
    for (const auto candidate : {LegendPosition::UpperRight, LegendPosition::UpperLeft,
                                 LegendPosition::LowerLeft, LegendPosition::LowerRight}) {
      const double c = coverage(axes, L, legendBox(candidate, L, w, h, m.pad).grown(m.pad * 0.5));
      if (c < best) best = c, position = candidate;
    }
  }
  const PixelRect box =
      position == LegendPosition::Outside
          ? PixelRect{std::round(L.right_px + m.pad), L.top_px, std::round(L.right_px + m.pad + w),
                      std::round(L.top_px + h)}
          : legendBox(position, L, w, h, m.pad);
  Triangles fill, edge;
  appendRect(fill, box);
  canvas.fill(fill, kLegendFill);
  appendRectOutline(edge, box, m.line);
  canvas.fill(edge, kLegendEdge);
  for (std::size_t k = 0; k < entries.size(); ++k) {
    const double y = box.top + m.pad * 0.75 + row * (static_cast<double>(k) + 0.5);
    drawLegendSample(canvas, entries[k], box.left + m.pad, box.left + m.pad + sample, y);
    texts.push_back({entries[k].label, m.legend_font, box.left + 2 * m.pad + sample, y,
                     HAlign::Left, VAlign::Middle});
  }
}

}  // namespace slamprep::eval::plot
