#include "slamprep/eval/plot/geometry.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

namespace slamprep::eval::plot {
namespace {

void appendQuad(Triangles& out, const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  out.insert(out.end(), {a, b, c, a, c, d});
}

double distance(const Vec2& a, const Vec2& b) {
  return std::hypot(b.x - a.x, b.y - a.y);
}

Vec2 lerp(const Vec2& a, const Vec2& b, double t) {
  return {a.x + (b.x - a.x) * t, a.y + (b.y - a.y) * t};
}

void appendPolygon(Triangles& out, const Vec2& center, const std::vector<Vec2>& ring) {
  for (std::size_t i = 0; i < ring.size(); ++i) {
    out.insert(out.end(), {center, ring[i], ring[(i + 1) % ring.size()]});
  }
}

/// Regular polygon with `sides` corners on a circle of `radius`, first corner at `phase_rad`
/// (measured from +x towards +y, i.e. clockwise on screen).
std::vector<Vec2> regularRing(const Vec2& c, double radius, int sides, double phase_rad) {
  std::vector<Vec2> ring;
  for (int i = 0; i < sides; ++i) {
    const double angle = phase_rad + 2.0 * std::numbers::pi * i / sides;
    ring.push_back({c.x + radius * std::cos(angle), c.y + radius * std::sin(angle)});
  }
  return ring;
}

/// A bar of width w from p in direction (cos a, sin a) with half-length h either side.
void appendBar(Triangles& out, const Vec2& c, double half_length, double width, double angle) {
  const Vec2 d{std::cos(angle) * half_length, std::sin(angle) * half_length};
  appendStroke(out, {{c.x - d.x, c.y - d.y}, {c.x + d.x, c.y + d.y}}, width);
}

/// Whether the wedge left open between two butt-ended quads meeting at b is wider than 0.05 px
/// (half-width * sin(turn angle)); below that a join disc is invisible and only costs triangles.
bool turnsVisibly(const Vec2& a, const Vec2& b, const Vec2& c, double half_width) {
  const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - b.x, vy = c.y - b.y;
  const double lengths = std::hypot(ux, uy) * std::hypot(vx, vy);
  if (lengths < 1e-18) return true;
  const double cross = std::abs(ux * vy - uy * vx), dot = ux * vx + uy * vy;
  return dot < 0.0 || half_width * cross / lengths > 0.05;
}

}  // namespace

void appendStroke(Triangles& out, const std::vector<Vec2>& polyline, double width_px) {
  const double half = width_px / 2.0;
  for (std::size_t i = 0; i + 1 < polyline.size(); ++i) {
    const Vec2& a = polyline[i];
    const Vec2& b = polyline[i + 1];
    const double length = distance(a, b);
    if (length < 1e-9) continue;
    const Vec2 n{-(b.y - a.y) / length * half, (b.x - a.x) / length * half};  // Eq.: unit normal
    appendQuad(out, {a.x + n.x, a.y + n.y}, {b.x + n.x, b.y + n.y}, {b.x - n.x, b.y - n.y},
               {a.x - n.x, a.y - n.y});
    if (i > 0 && turnsVisibly(polyline[i - 1], a, b, half)) appendDisc(out, a, half);  // round join
  }
}

std::pair<double, double> dashPattern(double width_px) {
  return {3.0 * width_px + 4.0, 2.0 * width_px + 3.0};
}

std::vector<std::vector<Vec2>> dashPolyline(const std::vector<Vec2>& polyline, double on_px,
                                            double off_px) {
  assert(on_px > 0.0 && off_px > 0.0);
  std::vector<std::vector<Vec2>> dashes;
  bool drawing = true;
  double left = on_px;  // length left in the current dash or gap
  if (!polyline.empty()) dashes.push_back({polyline.front()});
  for (std::size_t i = 0; i + 1 < polyline.size(); ++i) {
    const Vec2& a = polyline[i];
    const Vec2& b = polyline[i + 1];
    const double length = distance(a, b);
    double t = 0.0;  // arc length done on this segment
    while (length - t > left) {
      t += left;
      const Vec2 p = lerp(a, b, t / length);
      if (drawing) {
        dashes.back().push_back(p);
      } else {
        dashes.push_back({p});
      }
      drawing = !drawing;
      left = drawing ? on_px : off_px;
    }
    left -= length - t;
    if (drawing) dashes.back().push_back(b);
  }
  std::erase_if(dashes, [](const std::vector<Vec2>& d) { return d.size() < 2; });
  return dashes;
}

void appendDisc(Triangles& out, const Vec2& center, double radius_px) {
  // Chord error r (1 - cos(pi/n)) stays below 0.05 px: n >= pi / acos(1 - 0.05/r).
  const double ratio = std::clamp(1.0 - 0.05 / std::max(radius_px, 0.05), -1.0, 1.0);
  const int sides =
      std::clamp(static_cast<int>(std::ceil(std::numbers::pi / std::acos(ratio))), 8, 96);
  appendPolygon(out, center, regularRing(center, radius_px, sides, 0.0));
}

void appendRect(Triangles& out, const PixelRect& r) {
  appendQuad(out, {r.left, r.top}, {r.right, r.top}, {r.right, r.bottom}, {r.left, r.bottom});
}

void appendRectOutline(Triangles& out, const PixelRect& r, double w) {
  appendRect(out, {r.left, r.top, r.right, r.top + w});
  appendRect(out, {r.left, r.bottom - w, r.right, r.bottom});
  appendRect(out, {r.left, r.top + w, r.left + w, r.bottom - w});
  appendRect(out, {r.right - w, r.top + w, r.right, r.bottom - w});
}

void appendMarker(Triangles& out, Marker marker, const Vec2& c, double size_px,
                  double line_width_px) {
  const double r = size_px / 2.0;
  constexpr double kPi = std::numbers::pi;
  switch (marker) {
    case Marker::Circle:
      appendDisc(out, c, r);
      break;
    case Marker::Square:  // area matched to the circle: side = r sqrt(pi)
      appendRect(out, {c.x - 0.886 * r, c.y - 0.886 * r, c.x + 0.886 * r, c.y + 0.886 * r});
      break;
    case Marker::Triangle:  // pointing up; centroid at c
      appendPolygon(out, c, regularRing(c, 1.35 * r, 3, -kPi / 2));
      break;
    case Marker::TriangleDown:
      appendPolygon(out, c, regularRing(c, 1.35 * r, 3, kPi / 2));
      break;
    case Marker::Diamond:
      appendPolygon(out, c, regularRing(c, 1.15 * r, 4, 0.0));
      break;
    case Marker::Plus:
      appendBar(out, c, r, line_width_px, 0.0);
      appendBar(out, c, r, line_width_px, kPi / 2);
      break;
    case Marker::Cross:
      appendBar(out, c, r, line_width_px, kPi / 4);
      appendBar(out, c, r, line_width_px, -kPi / 4);
      break;
    case Marker::Auto:
      assert(false && "resolve Marker::Auto before tessellating");
      break;
  }
}

bool clipSegment(Vec2& a, Vec2& b, const PixelRect& rect) {
  // Liang-Barsky: p_k t <= q_k for the four edges.
  const double dx = b.x - a.x, dy = b.y - a.y;
  const double p[4] = {-dx, dx, -dy, dy};
  const double q[4] = {a.x - rect.left, rect.right - a.x, a.y - rect.top, rect.bottom - a.y};
  double t0 = 0.0, t1 = 1.0;
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0.0) {
      if (q[k] < 0.0) return false;
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0.0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
    if (t0 > t1) return false;
  }
  const Vec2 start = lerp(a, b, t0), end = lerp(a, b, t1);
  a = start, b = end;
  return true;
}

std::vector<std::vector<Vec2>> clipPolyline(const std::vector<Vec2>& polyline,
                                            const PixelRect& rect) {
  std::vector<std::vector<Vec2>> parts;
  if (polyline.size() == 1 && rect.contains(polyline[0])) parts.push_back(polyline);
  bool open = false;  // the last part ends at the previous vertex
  for (std::size_t i = 0; i + 1 < polyline.size(); ++i) {
    Vec2 a = polyline[i], b = polyline[i + 1];
    if (!clipSegment(a, b, rect)) {
      open = false;
      continue;
    }
    const bool starts_at_vertex = a.x == polyline[i].x && a.y == polyline[i].y;
    if (!open || !starts_at_vertex) parts.push_back({a});
    parts.back().push_back(b);
    open = b.x == polyline[i + 1].x && b.y == polyline[i + 1].y;
  }
  return parts;
}

}  // namespace slamprep::eval::plot
