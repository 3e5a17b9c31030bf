#include "slamprep/eval/plot/layout.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "slamprep/core/error.hpp"

namespace slamprep::eval::plot {
namespace {

constexpr double kMargin = 0.04;    ///< auto ranges extend the data by 4 % of the span each side
constexpr double kLargest = 1e300;  ///< larger magnitudes are treated as unusable (spans overflow)

/// Running min/max of usable values.
struct Span {
  double min = std::numeric_limits<double>::infinity();
  double max = -std::numeric_limits<double>::infinity();

  void add(double v) { min = std::min(min, v), max = std::max(max, v); }
  bool empty() const { return min > max; }
};

struct Extents {
  Span x, y;
  bool bars = false;  ///< some series draws bars (their base belongs in the y range)
};

Extents dataExtents(const Axes& axes) {
  Extents e;
  for (std::size_t i = 0; i < axes.series.size(); ++i) {
    const Series& s = axes.series[i];
    const bool bars = s.style == Style::Bars;
    const double offset = dodgeOffset(axes, i);
    const bool wide = bars || s.style == Style::Box;
    const double half_bar = wide ? barWidth(axes, i) / 2 : 0.0;
    for (std::size_t k = 0; k < s.x.size(); ++k) {
      const double x = s.x[k] + offset, y = s.y[k];
      if (!usable(x, axes.log_x) || !usable(y, axes.log_y)) continue;
      for (const double xe : {x - half_bar, x + half_bar}) {
        if (usable(xe, axes.log_x)) e.x.add(xe);
      }
      e.y.add(y);
      if (!s.y_err.empty() && std::isfinite(s.y_err[k])) {
        const double low = s.y_err_low.empty() ? s.y_err[k] : s.y_err_low[k];
        for (const double ye : {y - std::abs(low), y + std::abs(s.y_err[k])}) {
          if (usable(ye, axes.log_y)) e.y.add(ye);
        }
      }
    }
    if (bars && !axes.log_y) e.y.add(0.0), e.bars = true;
  }
  for (const Segments& segments : axes.segments) {
    for (const auto& [x0, y0, x1, y1] : segments.xyxy) {
      if (!usable(x0, axes.log_x) || !usable(y0, axes.log_y) || !usable(x1, axes.log_x) ||
          !usable(y1, axes.log_y)) {
        continue;
      }
      e.x.add(x0), e.x.add(x1), e.y.add(y0), e.y.add(y1);
    }
  }
  return e;
}

/// Data extent plus margins; a single value gets a symmetric range around it, a log axis at
/// least one decade.
Range autoRange(const Span& span, bool log_axis, bool bars) {
  if (span.empty()) return log_axis ? Range{1.0, 10.0} : Range{0.0, 1.0};
  if (log_axis) {
    double lo = std::log10(span.min), hi = std::log10(span.max);
    const double m = kMargin * (hi - lo);
    lo -= m, hi += m;
    // At least one decade: on a log axis a narrower range (0.0255 to 0.0262) makes values
    // that differ by 3 % look as far apart as ones that differ tenfold.
    if (hi - lo < 1.0) {
      const double centre = (lo + hi) / 2;
      lo = centre - 0.5, hi = centre + 0.5;
    }
    return {std::pow(10.0, lo), std::pow(10.0, hi)};
  }
  const double largest = std::max(std::abs(span.min), std::abs(span.max));
  if (span.max - span.min <= 1e-12 * largest) {
    const double half = largest == 0.0 ? 1.0 : 0.1 * largest;
    return {span.min - half, span.max + half};
  }
  const double m = kMargin * (span.max - span.min);
  Range r{span.min - m, span.max + m};
  if (bars && span.min == 0.0) r.min = 0.0;  // bars stand on the axis
  if (bars && span.max == 0.0) r.max = 0.0;
  return r;
}

/// Widens the range that is too short so that one unit spans equally many pixels in x and y.
void equalizeAspect(Range& x, Range& y, double width_px, double height_px) {
  const double ux = (x.max - x.min) / width_px, uy = (y.max - y.min) / height_px;
  if (ux > uy) {
    const double c = (y.min + y.max) / 2, half = ux * height_px / 2;
    y = {c - half, c + half};
  } else {
    const double c = (x.min + x.max) / 2, half = uy * width_px / 2;
    x = {c - half, c + half};
  }
}

std::vector<Tick> categoryTicks(const Axes& axes, const Range& x) {
  std::vector<Tick> ticks;
  for (std::size_t k = 0; k < axes.categories.size(); ++k) {
    const double value = static_cast<double>(k);
    if (value >= x.min && value <= x.max) ticks.push_back({value, axes.categories[k], true});
  }
  return ticks;
}

std::vector<Tick> axisTicks(const Range& r, bool log_axis, int max_major) {
  return log_axis ? logTicks(r, max_major) : linearTicks(r, max_major);
}

/// Widest major tick label.
double widestLabel(const std::vector<Tick>& ticks, double size, TextRenderer& text) {
  double widest = 0.0;
  for (const Tick& t : ticks) {
    if (t.major) widest = std::max(widest, text.measure(t.label, size).width_px);
  }
  return widest;
}

/// True when neighbouring x tick labels come closer than `gap_px`.
bool labelsCollide(const std::vector<Tick>& ticks, const PanelLayout& layout, double size,
                   double gap_px, TextRenderer& text) {
  double previous_right = -std::numeric_limits<double>::infinity();
  for (const Tick& t : ticks) {
    if (!t.major) continue;
    const double half = text.measure(t.label, size).width_px / 2;
    const double center = layout.toPixelX(t.value);
    if (center - half < previous_right + gap_px) return true;
    previous_right = center + half;
  }
  return false;
}

void checkRange(const std::optional<Range>& r, bool log_axis, const std::string& where) {
  if (!r) return;
  if (!std::isfinite(r->min) || !std::isfinite(r->max) || !(r->min < r->max)) {
    throw InputError(where, "range must be finite with min < max (got [" + std::to_string(r->min) +
                                ", " + std::to_string(r->max) + "])");
  }
  if (log_axis && r->min <= 0.0) {
    throw InputError(
        where, "a log axis needs a positive range minimum (got " + std::to_string(r->min) + ")");
  }
}

void validateSeries(const Series& s, const std::string& where) {
  if (s.x.size() != s.y.size()) {
    throw InputError(where, "x has " + std::to_string(s.x.size()) + " values but y has " +
                                std::to_string(s.y.size()));
  }
  if (!s.y_err_low.empty() && s.y_err_low.size() != s.y_err.size()) {
    throw InputError(where, "y_err_low has " + std::to_string(s.y_err_low.size()) +
                                " entries, y_err " + std::to_string(s.y_err.size()));
  }
  if (!s.y_err.empty() && s.y_err.size() != s.y.size()) {
    throw InputError(where, "y_err has " + std::to_string(s.y_err.size()) +
                                " values; it must be empty or match y (" +
                                std::to_string(s.y.size()) + ")");
  }
  if (!std::isfinite(s.line_width_px) || s.line_width_px <= 0.0 || s.line_width_px > 100.0) {
    throw InputError(where, "line_width_px must be in (0, 100]");
  }
  if (s.marker_size_px && (!std::isfinite(*s.marker_size_px) || *s.marker_size_px <= 0.0 ||
                           *s.marker_size_px > 200.0)) {
    throw InputError(where, "marker_size_px must be in (0, 200]");
  }
  if (s.bar_width && (!std::isfinite(*s.bar_width) || *s.bar_width <= 0.0)) {
    throw InputError(where, "bar_width must be positive");
  }
  if (s.style == Style::Box && !s.y_err.empty()) {
    throw InputError(where, "a box plot draws its own whiskers; y_err must be empty");
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

bool usable(double value, bool log_axis) {
  return std::isfinite(value) && std::abs(value) < kLargest &&
         (!log_axis || value > 1.0 / kLargest);
}

double dodgeOffset(const Axes& axes, std::size_t index) {
  const std::size_t n = axes.series.size();
  if (axes.categories.empty() || !axes.dodge || n < 2) return 0.0;
  // Bars and boxes share 80 % of a category; markers with error bars read better closer
  // together (50 %).
  const bool bars = std::any_of(axes.series.begin(), axes.series.end(), [](const Series& s) {
    return s.style == Style::Bars || s.style == Style::Box;
  });
  const double slot = (bars ? 0.8 : 0.5) / static_cast<double>(n);
  return (static_cast<double>(index) - (static_cast<double>(n) - 1.0) / 2.0) * slot;
}

double barWidth(const Axes& axes, std::size_t index) {
  const Series& s = axes.series[index];
  if (s.bar_width) return *s.bar_width;
  if (!axes.categories.empty()) return 0.8 / static_cast<double>(axes.series.size()) * 0.9;
  std::vector<double> xs;
  for (const double x : s.x) {
    if (usable(x, axes.log_x)) xs.push_back(x);
  }
  std::sort(xs.begin(), xs.end());
  double closest = std::numeric_limits<double>::infinity();
  for (std::size_t k = 1; k < xs.size(); ++k) {
    if (xs[k] > xs[k - 1]) closest = std::min(closest, xs[k] - xs[k - 1]);
  }
  return std::isfinite(closest) ? 0.8 * closest : 0.8;
}

Metrics metricsFor(const Figure& figure) {
  const double s = figure.font_scale;
  Metrics m;
  m.tick_font *= s, m.label_font *= s, m.title_font *= s;
  m.figure_title_font *= s, m.legend_font *= s;
  m.pad *= s, m.tick_length *= s;
  m.line = std::max(1.0, std::round(s));
  return m;
}

void validateFigure(const Figure& f) {
  const std::string name = "plot figure" + (f.title.empty() ? "" : " \"" + f.title + "\"");
  if (f.width_px < 32 || f.height_px < 32 || f.width_px > 8192 || f.height_px > 8192) {
    throw InputError(name, "size must be within 32..8192 px (got " + std::to_string(f.width_px) +
                               "x" + std::to_string(f.height_px) + ")");
  }
  if (f.rows < 1 || f.cols < 1 || f.rows > 16 || f.cols > 16) {
    throw InputError(name, "rows and cols must be within 1..16");
  }
  const auto gridded = static_cast<std::size_t>(
      std::count_if(f.axes.begin(), f.axes.end(), [](const Axes& a) { return !a.inset; }));
  if (gridded > static_cast<std::size_t>(f.rows * f.cols)) {
    throw InputError(name, std::to_string(gridded) + " axes do not fit a " +
                               std::to_string(f.rows) + "x" + std::to_string(f.cols) + " grid");
  }
  if (!std::isfinite(f.font_scale) || f.font_scale <= 0.0 || f.font_scale > 10.0) {
    throw InputError(name, "font_scale must be in (0, 10]");
  }
  if (f.supersample < 1 || f.supersample > 4) {
    throw InputError(name, "supersample must be within 1..4");
  }
  for (std::size_t i = 0; i < f.axes.size(); ++i) {
    const Axes& a = f.axes[i];
    const std::string where = name + ": axes[" + std::to_string(i) + "]";
    if (a.inset) {
      const auto& r = *a.inset;
      if (!(r[0] >= 0.0 && r[0] < r[2] && r[2] <= 1.0 && r[1] >= 0.0 && r[1] < r[3] && r[3] <= 1.0))
        throw InputError(where + ".inset",
                         "must be fractions left < right, top < bottom in [0, 1]");
    }
    checkRange(a.x_range, a.log_x, where + ".x_range");
    checkRange(a.y_range, a.log_y, where + ".y_range");
    if (!a.categories.empty() && a.log_x) {
      throw InputError(where, "categorical x axes cannot be logarithmic");
    }
    for (std::size_t j = 0; j < a.series.size(); ++j) {
      const std::string label = a.series[j].label;
      validateSeries(a.series[j], where + ".series[" + std::to_string(j) + "]" +
                                      (label.empty() ? "" : " \"" + label + "\""));
    }
    for (std::size_t j = 0; j < a.segments.size(); ++j) {
      const double w = a.segments[j].line_width_px;
      if (!std::isfinite(w) || w <= 0.0 || w > 100.0) {
        throw InputError(where + ".segments[" + std::to_string(j) + "]",
                         "line_width_px must be in (0, 100]");
      }
    }
  }
}

namespace {

/// The ticks of a panel of w x h pixels: as many as fit, the x labels thinned until none collide.
void chooseTicks(const Axes& axes, const Metrics& m, TextRenderer& text, double w, double h,
                 PanelPlan& plan) {
  const PanelLayout& L = plan.layout;
  const int max_y = std::clamp(static_cast<int>(h / (5.0 * m.tick_font)), 2, 8);
  plan.y_ticks = axisTicks(L.y, axes.log_y, max_y);
  if (!axes.categories.empty()) {
    plan.x_ticks = categoryTicks(axes, L.x);
    return;
  }
  int max_x = std::clamp(static_cast<int>(w / (7.0 * m.tick_font)), 2, 9);
  plan.x_ticks = axisTicks(L.x, axes.log_x, max_x);
  while (max_x > 2 && labelsCollide(plan.x_ticks, L, m.tick_font, 1.5 * m.pad, text))
    plan.x_ticks = axisTicks(L.x, axes.log_x, --max_x);
}

PanelPlan planPanel(const Axes& axes, const PixelRect& cell, const Metrics& m, TextRenderer& text) {
  const Extents extents = dataExtents(axes);
  const Range base_x = axes.x_range               ? *axes.x_range
                       : !axes.categories.empty() ? Range{-0.5, axes.categories.size() - 0.5}
                                                  : autoRange(extents.x, axes.log_x, false);
  const Range base_y =
      axes.y_range ? *axes.y_range : autoRange(extents.y, axes.log_y, extents.bars);

  const double tick_h = text.measure("0", m.tick_font).height();
  const double label_h = text.measure("Ag", m.label_font).height();
  const double title_h = axes.title.empty() ? 0.0 : text.measure(axes.title, m.title_font).height();
  const double top = axes.title.empty() ? std::max(m.pad * 1.5, tick_h * 0.6 + m.pad * 0.5)
                                        : m.pad * 0.5 + title_h + m.pad;
  const double bottom = m.tick_length + m.pad * 0.5 + tick_h +
                        (axes.x_label.empty() ? 0.0 : m.pad * 0.5 + label_h) + m.pad;
  const double label_column = axes.y_label.empty() ? 0.0 : label_h + m.pad * 0.75;
  double left = m.pad + label_column + 3.0 * m.tick_font + m.pad * 0.5 + m.tick_length;
  const double legend =
      axes.legend == LegendPosition::Outside ? outsideLegendWidth(axes, m, text) + m.pad : 0.0;
  double right = 2.0 * m.pad + legend;

  PanelPlan plan;
  plan.cell = cell;
  for (int pass = 0; pass < 3; ++pass) {
    PanelLayout& L = plan.layout;
    L.left_px = std::round(cell.left + left);
    L.top_px = std::round(cell.top + top);
    L.right_px = std::max(L.left_px + 1.0, std::round(cell.right - right));
    L.bottom_px = std::max(L.top_px + 1.0, std::round(cell.bottom - bottom));
    L.log_x = axes.log_x, L.log_y = axes.log_y;
    L.x = base_x, L.y = base_y;
    const double w = L.right_px - L.left_px, h = L.bottom_px - L.top_px;
    if (axes.equal_aspect && !axes.log_x && !axes.log_y) equalizeAspect(L.x, L.y, w, h);

    chooseTicks(axes, m, text, w, h, plan);

    // Margins that fit the labels just measured; the next pass uses them.
    left = m.pad + label_column + widestLabel(plan.y_ticks, m.tick_font, text) + m.pad * 0.5 +
           m.tick_length;
    right = 2.0 * m.pad + legend;
    for (const Tick& t : plan.x_ticks) {
      if (!t.major) continue;
      const double half = text.measure(t.label, m.tick_font).width_px / 2;
      const double overhang_right = L.toPixelX(t.value) + half - L.right_px;
      const double overhang_left = L.left_px - (L.toPixelX(t.value) - half);
      right = std::max(right, overhang_right + m.pad);
      left = std::max(left, overhang_left + m.pad);
    }
  }
  return plan;
}

}  // namespace

FigurePlan planFigure(const Figure& figure, TextRenderer& text) {
  FigurePlan plan;
  plan.metrics = metricsFor(figure);
  const Metrics& m = plan.metrics;
  double top = m.pad * 0.5;
  if (!figure.title.empty()) {
    const double h = text.measure(figure.title, m.figure_title_font).height();
    plan.title_center_y = m.pad + h / 2;
    top = m.pad * 1.5 + h;
  }
  const PixelRect area{m.pad * 0.5, top, figure.width_px - m.pad * 0.5,
                       figure.height_px - m.pad * 0.5};
  const double cell_w = (area.right - area.left) / figure.cols;
  const double cell_h = (area.bottom - area.top) / figure.rows;
  int grid_index = 0;  // insets take no place in the grid
  for (const Axes& axes : figure.axes) {
    PixelRect cell;
    if (axes.inset) {
      const auto& f = *axes.inset;
      cell = {f[0] * figure.width_px, f[1] * figure.height_px, f[2] * figure.width_px,
              f[3] * figure.height_px};
    } else {
      const int row = grid_index / figure.cols, col = grid_index % figure.cols;
      ++grid_index;
      cell = {area.left + col * cell_w, area.top + row * cell_h, area.left + (col + 1) * cell_w,
              area.top + (row + 1) * cell_h};
    }
    plan.panels.push_back(planPanel(axes, cell, m, text));
  }
  return plan;
}

}  // namespace slamprep::eval::plot
