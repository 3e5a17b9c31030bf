#include <algorithm>
#include <cmath>

#include "slamprep/eval/plot/draw.hpp"

namespace slamprep::eval::plot {
namespace {

const Color kGrid{0.88, 0.88, 0.88, 1.0};       ///< major grid
const Color kMinorGrid{0.95, 0.95, 0.95, 1.0};  ///< minor grid (log axes)

/// Pixel column/row whose centre is nearest to `px`, as the rectangle [c, c + width).
double snap(double px) {
  return std::floor(px);
}

}  // namespace

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

}  // namespace slamprep::eval::plot
