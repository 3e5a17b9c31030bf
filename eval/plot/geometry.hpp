#pragma once
// Tessellation in pixel space: thick polylines (round joins), dashes, markers, rectangles, all as
// triangle lists for the GL canvas, plus segment clipping.

#include <vector>

#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot {

/// A point in pixels, origin top left, y down.
struct Vec2 {
  double x = 0.0;
  double y = 0.0;
};

/// A triangle list: every three vertices form one triangle.
using Triangles = std::vector<Vec2>;

/// An axis-aligned pixel rectangle.
struct PixelRect {
  double left = 0.0;
  double top = 0.0;
  double right = 0.0;
  double bottom = 0.0;

  PixelRect grown(double by) const { return {left - by, top - by, right + by, bottom + by}; }
  bool contains(const Vec2& p) const {
    return p.x >= left && p.x <= right && p.y >= top && p.y <= bottom;
  }
};

/// Stroke of `width_px` along the polyline: a quad per segment, a disc at every interior joint
/// (round join), butt ends.
void appendStroke(Triangles& out, const std::vector<Vec2>& polyline, double width_px);

/// Splits a polyline into dashes of `on_px` separated by gaps of `off_px`; the pattern runs on
/// across vertices.
std::vector<std::vector<Vec2>> dashPolyline(const std::vector<Vec2>& polyline, double on_px,
                                            double off_px);

/// Dash pattern (on, off) in pixels for a stroke of this width.
std::pair<double, double> dashPattern(double width_px);

/// Filled disc; the number of sides grows with the radius.
void appendDisc(Triangles& out, const Vec2& center, double radius_px);

/// Filled rectangle.
void appendRect(Triangles& out, const PixelRect& rect);

/// Rectangle outline of `width_px`, drawn inside the rectangle.
void appendRectOutline(Triangles& out, const PixelRect& rect, double width_px);

/// A filled marker of extent `size_px` centred at `center` (Plus/Cross use `line_width_px`).
/// `marker` must not be Auto.
void appendMarker(Triangles& out, Marker marker, const Vec2& center, double size_px,
                  double line_width_px);

/// Liang-Barsky: clips segment a-b to the rectangle in place; false when nothing is left.
bool clipSegment(Vec2& a, Vec2& b, const PixelRect& rect);

/// Clips a polyline to the rectangle; the parts that stay inside, each a polyline.
std::vector<std::vector<Vec2>> clipPolyline(const std::vector<Vec2>& polyline,
                                            const PixelRect& rect);

}  // namespace slamprep::eval::plot
