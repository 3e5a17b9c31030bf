#include <algorithm>
#include <cassert>
#include <cmath>

#include "eval/plot/gl_canvas.hpp"
#include "eval/plot/layout.hpp"
#include "eval/plot/plot.hpp"
#include "eval/plot/text.hpp"

namespace slamprep::eval::plot {
namespace {

const Color kWhite{1.0, 1.0, 1.0, 1.0};
const Color kInk{0.13, 0.13, 0.13, 1.0};         ///< frame, ticks and text
const Color kGrid{0.88, 0.88, 0.88, 1.0};        ///< major grid
const Color kMinorGrid{0.95, 0.95, 0.95, 1.0};   ///< minor grid (log axes)
const Color kLegendFill{1.0, 1.0, 1.0, 0.88};    ///< legend background
const Color kLegendEdge{0.80, 0.80, 0.80, 1.0};  ///< legend border

constexpr Marker kMarkerCycle[] = {Marker::Circle, Marker::Square, Marker::Triangle,
                                   Marker::Diamond, Marker::TriangleDown};

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

std::vector<Look> resolveLooks(const Axes& axes) {
  std::vector<Look> looks;
  std::size_t automatic = 0;  // palette slot of the next series without a colour
  for (std::size_t i = 0; i < axes.series.size(); ++i) {
    const Series& s = axes.series[i];
    Look look;
    look.color = s.color ? *s.color : paletteColor(automatic++);
    look.marker = s.marker != Marker::Auto ? s.marker : kMarkerCycle[i % std::size(kMarkerCycle)];
    look.marker_size = s.marker_size_px.value_or(s.style == Style::Points ? 3.0 : 8.0);
    looks.push_back(look);
  }
  return looks;
}

PixelRect plotRect(const PanelLayout& L) {
  return {L.left_px, L.top_px, L.right_px, L.bottom_px};
}

/// Pixel column/row whose centre is nearest to `px`, as the rectangle [c, c + width).
double snap(double px) {
  return std::floor(px);
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

void drawGrid(GlCanvas& canvas, const PanelPlan& plan, const Axes& axes, const Metrics& m) {
  const PanelLayout& L = plan.layout;
  Triangles major, minor;
  // Minor grid lines only where a decade is tall/wide enough for them not to become a texture.
  constexpr double kMinDecadeForMinorGrid_px = 100.0;
  const bool minor_x = L.log_x && (L.right_px - L.left_px) / std::log10(L.x.max / L.x.min) >=
                                      kMinDecadeForMinorGrid_px;
  const bool minor_y = L.log_y && (L.bottom_px - L.top_px) / std::log10(L.y.max / L.y.min) >=
                                      kMinDecadeForMinorGrid_px;
  const bool categorical = !axes.categories.empty();
  for (const Tick& t : plan.x_ticks) {
    if (categorical) break;
    if (!t.major && !minor_x) continue;
    const double x = snap(L.toPixelX(t.value));
    if (x <= L.left_px || x + m.line >= L.right_px) continue;  // the frame is there
    appendRect(t.major ? major : minor, {x, L.top_px, x + m.line, L.bottom_px});
  }
  for (const Tick& t : plan.y_ticks) {
    if (!t.major && !minor_y) continue;
    const double y = snap(L.toPixelY(t.value));
    if (y <= L.top_px || y + m.line >= L.bottom_px) continue;
    appendRect(t.major ? major : minor, {L.left_px, y, L.right_px, y + m.line});
  }
  canvas.fill(minor, kMinorGrid);
  canvas.fill(major, kGrid);
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
    if (!usable(x, axes.log_x) || !usable(y, axes.log_y) || !std::isfinite(e) || e == 0.0) continue;
    const double px = L.toPixelX(x);
    const double top = L.toPixelY(y + e);
    const bool low_ok = usable(y - e, axes.log_y);
    const double bottom = low_ok ? L.toPixelY(y - e) : L.bottom_px + 2.0 * width;
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

void drawSeries(GlCanvas& canvas, const Axes& axes, std::size_t i, const PanelLayout& L,
                const Look& look) {
  const Series& s = axes.series[i];
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

void drawFrameAndTicks(GlCanvas& canvas, const PanelPlan& plan, const Metrics& m,
                       std::vector<TextItem>& texts) {
  const PanelLayout& L = plan.layout;
  Triangles ink;
  appendRectOutline(ink, plotRect(L), m.line);
  const double minor_length = 0.6 * m.tick_length;
  for (const Tick& t : plan.x_ticks) {
    const double x = std::clamp(snap(L.toPixelX(t.value)), L.left_px, L.right_px - m.line);
    const double length = t.major ? m.tick_length : minor_length;
    appendRect(ink, {x, L.bottom_px, x + m.line, L.bottom_px + length});
    if (t.major) {
      texts.push_back({t.label, m.tick_font, x + m.line / 2,
                       L.bottom_px + m.tick_length + m.pad * 0.5, HAlign::Center, VAlign::Top});
    }
  }
  for (const Tick& t : plan.y_ticks) {
    const double y = std::clamp(snap(L.toPixelY(t.value)), L.top_px, L.bottom_px - m.line);
    const double length = t.major ? m.tick_length : minor_length;
    appendRect(ink, {L.left_px - length, y, L.left_px, y + m.line});
    if (t.major) {
      texts.push_back({t.label, m.tick_font, L.left_px - m.tick_length - m.pad * 0.5,
                       y + m.line / 2, HAlign::Right, VAlign::Middle});
    }
  }
  canvas.fill(ink, kInk);
}

// ---- legend ----

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
  }
  canvas.fill(shape, e.look.color, false);
}

void drawLegend(GlCanvas& canvas, const Axes& axes, const PanelLayout& L,
                const std::vector<Look>& looks, const Metrics& m, TextRenderer& text,
                std::vector<TextItem>& texts) {
  if (axes.legend == LegendPosition::None) return;
  const auto entries = legendEntries(axes, looks);
  if (entries.empty()) return;
  const double row = 1.5 * m.legend_font;
  const double sample = 2.4 * m.legend_font;
  double widest = 0.0;
  for (const auto& e : entries)
    widest = std::max(widest, text.measure(e.label, m.legend_font).width_px);
  const double w = m.pad + sample + m.pad + widest + m.pad * 1.25;
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
  const PixelRect box = legendBox(position, L, w, h, m.pad);
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

void queueAxisLabels(const Axes& axes, const PanelPlan& plan, const Metrics& m, TextRenderer& text,
                     std::vector<TextItem>& texts) {
  const PanelLayout& L = plan.layout;
  const double center_x = (L.left_px + L.right_px) / 2, center_y = (L.top_px + L.bottom_px) / 2;
  if (!axes.title.empty()) {
    texts.push_back(
        {axes.title, m.title_font, center_x, L.top_px - m.pad, HAlign::Center, VAlign::Bottom});
  }
  if (!axes.x_label.empty()) {
    const double tick_h = text.measure("0", m.tick_font).height();
    texts.push_back({axes.x_label, m.label_font, center_x,
                     L.bottom_px + m.tick_length + m.pad + tick_h, HAlign::Center, VAlign::Top});
  }
  if (!axes.y_label.empty()) {  // rotated, reading upwards, at the left edge of the cell
    texts.push_back({axes.y_label, m.label_font, plan.cell.left + m.pad, center_y, HAlign::Center,
                     VAlign::Top, true});
  }
}

}  // namespace

double PanelLayout::toPixelX(double x_data) const {
  const double f =
      log_x ? (std::log10(x_data) - std::log10(x.min)) / (std::log10(x.max) - std::log10(x.min))
            : (x_data - x.min) / (x.max - x.min);
  return left_px + f * (right_px - left_px);
}

double PanelLayout::toPixelY(double y_data) const {
  const double f =
      log_y ? (std::log10(y_data) - std::log10(y.min)) / (std::log10(y.max) - std::log10(y.min))
            : (y_data - y.min) / (y.max - y.min);
  return bottom_px - f * (bottom_px - top_px);
}

std::array<std::uint8_t, 4> Image::pixel(int x, int y) const {
  assert(x >= 0 && y >= 0 && x < width && y < height);
  const std::size_t i = (static_cast<std::size_t>(y) * width + x) * 4;
  return {rgba[i], rgba[i + 1], rgba[i + 2], rgba[i + 3]};
}

Color rgb(std::uint32_t hex, double alpha) {
  return {((hex >> 16) & 0xFF) / 255.0, ((hex >> 8) & 0xFF) / 255.0, (hex & 0xFF) / 255.0, alpha};
}

const std::vector<Color>& defaultPalette() {
  // Okabe & Ito (2008), "Color Universal Design"; yellow last, it is faint on white.
  static const std::vector<Color> palette{rgb(0x0072B2), rgb(0xD55E00), rgb(0x009E73),
                                          rgb(0xCC79A7), rgb(0xE69F00), rgb(0x56B4E9),
                                          rgb(0x000000), rgb(0xF0E442)};
  return palette;
}

Color paletteColor(std::size_t i) {
  return defaultPalette()[i % defaultPalette().size()];
}

std::vector<PanelLayout> layoutFigure(const Figure& figure) {
  validateFigure(figure);
  TextRenderer text(figure.font_path);
  std::vector<PanelLayout> layouts;
  for (const PanelPlan& panel : planFigure(figure, text).panels) layouts.push_back(panel.layout);
  return layouts;
}

Image render(const Figure& figure) {
  validateFigure(figure);
  TextRenderer text(figure.font_path);
  const FigurePlan plan = planFigure(figure, text);
  const Metrics& m = plan.metrics;
  std::vector<TextItem> texts;
  if (!figure.title.empty()) {
    texts.push_back({figure.title, m.figure_title_font, figure.width_px / 2.0, plan.title_center_y,
                     HAlign::Center, VAlign::Middle});
  }

  GlCanvas canvas(figure.width_px, figure.height_px, figure.supersample);
  canvas.clear(kWhite);
  for (std::size_t i = 0; i < figure.axes.size(); ++i) {
    const Axes& axes = figure.axes[i];
    const PanelPlan& panel = plan.panels[i];
    const PanelLayout& L = panel.layout;
    const auto looks = resolveLooks(axes);
    canvas.setClip(plotRect(L));
    if (axes.grid) drawGrid(canvas, panel, axes, m);
    drawSegments(canvas, axes, L);
    for (std::size_t k = 0; k < axes.series.size(); ++k) drawSeries(canvas, axes, k, L, looks[k]);
    canvas.clearClip();
    drawFrameAndTicks(canvas, panel, m, texts);
    drawLegend(canvas, axes, L, looks, m, text, texts);
    queueAxisLabels(axes, panel, m, text, texts);
  }
  Image image = canvas.read();
  for (const TextItem& t : texts) {
    text.draw(image, t.text, t.size, t.x, t.y, t.h, t.v, kInk, t.vertical);
  }
  return image;
}

void renderPng(const Figure& figure, const std::filesystem::path& path) {
  writePng(render(figure), path);
}

}  // namespace slamprep::eval::plot
