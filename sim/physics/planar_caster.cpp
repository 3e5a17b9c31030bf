#include "slamprep/sim/physics/planar_caster.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>

namespace slamprep::sim {
namespace {

double cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  return a.x() * b.y() - a.y() * b.x();
}

/// True when segment a-b meets the axis-aligned box [lo, hi] (Liang-Barsky clipping).
bool segmentTouchesBox(const Eigen::Vector2d& a, const Eigen::Vector2d& b,
                       const Eigen::Vector2d& lo, const Eigen::Vector2d& hi) {
  double t0 = 0.0, t1 = 1.0;
  const Eigen::Vector2d e = b - a;
  for (int k = 0; k < 2; ++k) {
    if (e[k] == 0.0) {
      if (a[k] < lo[k] || a[k] > hi[k]) return false;
      continue;
    }
    double ta = (lo[k] - a[k]) / e[k], tb = (hi[k] - a[k]) / e[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

}  // namespace

PlanarCaster::PlanarCaster(const World& world, const PlanarCasterParams& params)
    : edge_tolerance_(params.edge_tolerance) {
  assert(params.edge_tolerance > -1e-6 && params.cells_per_primitive > 0);
  // Glass (returns: false) gives no return: the ray goes on to whatever stands behind it.
  for (const Wall& wall : world.walls)
    if (wall.returns) addPrism(footprint(wall), wall.height_m);
  for (const Box& box : world.boxes)
    if (box.returns) addPrism(footprint(box), box.height_m);
  for (const Polygon& poly : world.polygons)
    if (poly.returns) addPrism(poly.vertices_m, poly.height_m);
  for (const Cylinder& c : world.cylinders)
    if (c.returns) circles_.push_back({c.center_m, c.radius_m, c.height_m});
  buildGrid(params.cells_per_primitive);
}

void PlanarCaster::addPrism(const std::vector<Eigen::Vector2d>& outline, double height_m) {
  // Same orientation as the Bullet mesh (scene.cpp): counter-clockwise, positive shoelace area.
  double area2 = 0.0;
  for (std::size_t i = 0; i < outline.size(); ++i)
    area2 += cross(outline[i], outline[(i + 1) % outline.size()]);
  const std::size_t n = outline.size();
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = area2 < 0 ? n - 1 - i : i;  // reversed when clockwise
    const std::size_t k = area2 < 0 ? (2 * n - 2 - i) % n : (i + 1) % n;
    segments_.push_back({outline[j], outline[k], height_m});
  }
}

void PlanarCaster::buildGrid(double cells_per_primitive) {
  const std::size_t n = segments_.size() + circles_.size();
  if (n == 0) return;
  Eigen::Vector2d lo = Eigen::Vector2d::Constant(std::numeric_limits<double>::infinity());
  Eigen::Vector2d hi = -lo;
  std::vector<std::pair<Eigen::Vector2d, Eigen::Vector2d>> boxes;  // per primitive
  for (const Segment& s : segments_) {
    // With an edge tolerance the segment reaches tolerance * length beyond its ends.
    const Eigen::Vector2d ext = std::max(edge_tolerance_, 0.0) * (s.b - s.a).cwiseAbs();
    boxes.emplace_back(s.a.cwiseMin(s.b) - ext, s.a.cwiseMax(s.b) + ext);
  }
  for (const Circle& c : circles_)
    boxes.emplace_back(c.center_m.array() - c.radius_m, c.center_m.array() + c.radius_m);
  for (const auto& [a, b] : boxes) {
    lo = lo.cwiseMin(a);
    hi = hi.cwiseMax(b);
  }
  // Primitives are registered in every cell they come within `pad` of, so a hit that rounding
  // places on the far side of a cell boundary is still found in the cell the ray is in.
  const double pad = 1e-9 * (1.0 + (hi - lo).maxCoeff() + lo.cwiseAbs().maxCoeff());
  min_m_ = lo.array() - 2 * pad;
  max_m_ = hi.array() + 2 * pad;
  const Eigen::Vector2d size = max_m_ - min_m_;
  constexpr double kMaxCellsPerAxis = 1024;
  cell_m_ = std::sqrt(size.x() * size.y() / (cells_per_primitive * static_cast<double>(n)));
  cell_m_ = std::max({cell_m_, size.x() / kMaxCellsPerAxis, size.y() / kMaxCellsPerAxis});
  nx_ = std::max(1, static_cast<int>(std::ceil(size.x() / cell_m_)));
  ny_ = std::max(1, static_cast<int>(std::ceil(size.y() / cell_m_)));

  auto cellIndex = [&](double v, double origin, int count) {
    return std::clamp(static_cast<int>(std::floor((v - origin) / cell_m_)), 0, count - 1);
  };
  // Two passes over the primitives' cells: count, then fill (compressed rows).
  std::vector<std::uint32_t> count(static_cast<std::size_t>(nx_) * ny_ + 1, 0);
  auto visit = [&](auto&& emit) {
    for (std::size_t p = 0; p < n; ++p) {
      const auto& [a, b] = boxes[p];
      for (int iy = cellIndex(a.y() - pad, min_m_.y(), ny_);
           iy <= cellIndex(b.y() + pad, min_m_.y(), ny_); ++iy)
        for (int ix = cellIndex(a.x() - pad, min_m_.x(), nx_);
             ix <= cellIndex(b.x() + pad, min_m_.x(), nx_); ++ix) {
          if (p < segments_.size()) {
            const Segment& s = segments_[p];
            const Eigen::Vector2d ext = edge_tolerance_ * (s.b - s.a);
            const Eigen::Vector2d cell_lo = min_m_ + cell_m_ * Eigen::Vector2d(ix, iy);
            const Eigen::Vector2d cell_hi = cell_lo + Eigen::Vector2d::Constant(cell_m_);
            if (!segmentTouchesBox(s.a - ext, s.b + ext, cell_lo.array() - pad,
                                   cell_hi.array() + pad))
              continue;
          }
          emit(static_cast<std::size_t>(iy) * nx_ + ix, static_cast<Ref>(p));
        }
    }
  };
  visit([&](std::size_t cell, Ref) { ++count[cell + 1]; });
  for (std::size_t k = 1; k < count.size(); ++k) count[k] += count[k - 1];
  cells_ = count;
  refs_.resize(count.back());
  visit([&](std::size_t cell, Ref p) { refs_[count[cell]++] = p; });
}

void PlanarCaster::testCell(std::size_t cell, const Eigen::Vector2d& o, const Eigen::Vector2d& d,
                            double height_m, double& best_t) const {
  const std::size_t nseg = segments_.size();
  for (std::uint32_t k = cells_[cell]; k < cells_[cell + 1]; ++k) {
    const Ref p = refs_[k];
    if (p < nseg) {
      const Segment& s = segments_[p];
      if (height_m > s.height_m) continue;
      // o + t d = a + u (b - a): t = (w x e) / (d x e), u = (w x d) / (d x e), w = a - o.
      const Eigen::Vector2d e = s.b - s.a, w = s.a - o;
      const double denom = cross(d, e);
      if (denom == 0.0) continue;  // parallel: Bullet's plane test sees no crossing either
      const double t = cross(w, e) / denom;
      if (!(t > 0.0 && t < best_t)) continue;
      const double u = cross(w, d) / denom;
      if (u < -edge_tolerance_ || u > 1.0 + edge_tolerance_) continue;
      best_t = t;
    } else {
      const Circle& c = circles_[p - nseg];
      if (height_m > c.height_m) continue;
      // |o + t d - c|^2 = r^2: t^2 + 2 b t + (|oc|^2 - r^2) = 0, nearer root from outside.
      const Eigen::Vector2d oc = o - c.center_m;
      const double b = oc.dot(d);
      const double disc = b * b - (oc.squaredNorm() - c.radius_m * c.radius_m);
      if (disc < 0.0) continue;
      const double t = -b - std::sqrt(disc);
      if (t > 0.0 && t < best_t) best_t = t;
    }
  }
}

std::optional<double> PlanarCaster::cast(const Eigen::Vector2d& origin_m,
                                         const Eigen::Vector2d& dir, double height_m,
                                         double max_range_m) const {
  assert(max_range_m > 0 && std::abs(dir.norm() - 1.0) < 1e-9);
  if (refs_.empty() || height_m < 0.0) return std::nullopt;
  // Clip the ray [0, max_range] to the grid's box (slabs).
  double t0 = 0.0, t1 = max_range_m;
  for (int k = 0; k < 2; ++k) {
    if (dir[k] == 0.0) {
      if (origin_m[k] < min_m_[k] || origin_m[k] > max_m_[k]) return std::nullopt;
      continue;
    }
    double ta = (min_m_[k] - origin_m[k]) / dir[k], tb = (max_m_[k] - origin_m[k]) / dir[k];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
  }
  if (t0 > t1) return std::nullopt;

  // Cell walk (Amanatides & Woo 1987): visit the cells the ray crosses in order; stop once the
  // best hit lies before the current cell's exit (no later cell can hold a nearer one).
  const Eigen::Vector2d entry = origin_m + t0 * dir;
  int ix = std::clamp(static_cast<int>(std::floor((entry.x() - min_m_.x()) / cell_m_)), 0, nx_ - 1);
  int iy = std::clamp(static_cast<int>(std::floor((entry.y() - min_m_.y()) / cell_m_)), 0, ny_ - 1);
  constexpr double kInf = std::numeric_limits<double>::infinity();
  auto axis = [&](int k, int i, int& step, double& t_next, double& t_delta) {
    step = dir[k] > 0 ? 1 : (dir[k] < 0 ? -1 : 0);
    if (step == 0) {
      t_next = t_delta = kInf;
      return;
    }
    const double boundary = min_m_[k] + cell_m_ * (step > 0 ? i + 1 : i);
    t_next = (boundary - origin_m[k]) / dir[k];
    t_delta = cell_m_ / std::abs(dir[k]);
  };
  int step_x = 0, step_y = 0;
  double next_x = 0, next_y = 0, delta_x = 0, delta_y = 0;
  axis(0, ix, step_x, next_x, delta_x);
  axis(1, iy, step_y, next_y, delta_y);

  double best_t = max_range_m;
  while (true) {
    testCell(static_cast<std::size_t>(iy) * nx_ + ix, origin_m, dir, height_m, best_t);
    const double t_exit = std::min(next_x, next_y);
    if (best_t <= t_exit || t_exit > t1) break;
    if (next_x < next_y) {
      ix += step_x;
      next_x += delta_x;
      if (ix < 0 || ix >= nx_) break;
    } else {
      iy += step_y;
      next_y += delta_y;
      if (iy < 0 || iy >= ny_) break;
    }
  }
  if (best_t < max_range_m) return best_t;
  return std::nullopt;
}

}  // namespace slamprep::sim
