#include "slamprep/eval/bench/twin_walls.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>
#include <numbers>

namespace slamprep::eval {
namespace {

/// One occupied grid cell: the centroid of its returns and the mean direction to their sensors.
struct Cell {
  Eigen::Vector2i index;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  Eigen::Vector2d view = Eigen::Vector2d::Zero();     ///< mean unit vector return -> sensor
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();  ///< covariance of its returns
  int hits = 0;
};

std::vector<Cell> occupiedCells(const std::vector<MapPoint>& points,
                                const WallExtractionParams& p) {
  std::map<std::pair<int, int>, Cell> grid;  // ordered: the same points give the same cells
  for (const MapPoint& m : points) {
    const int ix = static_cast<int>(std::floor(m.p_world.x() / p.cell_m));
    const int iy = static_cast<int>(std::floor(m.p_world.y() / p.cell_m));
    Cell& c = grid[{ix, iy}];
    c.index = {ix, iy};
    c.centroid += m.p_world;
    c.scatter += m.p_world * m.p_world.transpose();
    const Eigen::Vector2d to_sensor = m.sensor_world - m.p_world;
    if (to_sensor.norm() > 0.0) c.view += to_sensor.normalized();
    ++c.hits;
  }
  std::vector<Cell> cells;
  for (auto& [key, c] : grid) {
    if (c.hits < p.min_hits) continue;
    c.centroid /= c.hits;
    c.view /= c.hits;
    c.scatter = c.scatter / c.hits - c.centroid * c.centroid.transpose();
    cells.push_back(c);
  }
  return cells;
}

/// Total least squares line through `pts`: its centroid and unit direction (Eq. (1) of
/// docs/twin.md: the eigenvector of the scatter matrix with the largest eigenvalue).
std::pair<Eigen::Vector2d, Eigen::Vector2d> fitLine(const std::vector<Eigen::Vector2d>& pts) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& q : pts) mean += q;
  mean /= double(pts.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (const auto& q : pts) scatter += (q - mean) * (q - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig(scatter);
  return {mean, eig.eigenvectors().col(1)};
}

/// A segment along the line (mean, dir) over the cells `members`, its normal on the viewed side.
WallSegment makeSegment(const std::vector<Cell>& cells, const std::vector<int>& members,
                        double cell_m) {
  std::vector<Eigen::Vector2d> pts;
  Eigen::Vector2d view = Eigen::Vector2d::Zero();
  for (int i : members) {
    pts.push_back(cells[i].centroid);
    view += cells[i].view;
  }
  const auto [mean, dir] = fitLine(pts);
  double lo = 1e300, hi = -1e300, sq = 0.0, returns_sq = 0.0, returns = 0.0;
  const Eigen::Vector2d normal(-dir.y(), dir.x());
  for (int i : members) {
    const Cell& c = cells[i];
    const double along = (c.centroid - mean).dot(dir), off = (c.centroid - mean).dot(normal);
    lo = std::min(lo, along);
    hi = std::max(hi, along);
    sq += off * off;
    // Its returns' squared distance from the line: the centroid's plus their spread about it.
    returns_sq += c.hits * (off * off + normal.dot(c.scatter * normal));
    returns += c.hits;
  }
  WallSegment s;
  s.from_m = mean + (lo - 0.5 * cell_m) * dir;  // the cells' extent, not their centres'
  s.to_m = mean + (hi + 0.5 * cell_m) * dir;
  s.normal = view.dot(normal) >= 0.0 ? normal : Eigen::Vector2d(-normal);
  s.cells = static_cast<int>(members.size());
  s.rms_m = std::sqrt(sq / double(pts.size()));
  s.spread_m = std::sqrt(returns_sq / returns);
  return s;
}

/// Retires the active cells in the wall's noise (WallExtractionParams::fringe_sigmas): along
/// its extent and within max(line_tolerance_m, fringe_sigmas x spread_m) of its line.
template <typename Retire>
void retireFringe(const std::vector<Cell>& cells, const std::vector<char>& active,
                  const WallSegment& s, const WallExtractionParams& p, Retire retire) {
  const double band = std::max(p.line_tolerance_m, p.fringe_sigmas * s.spread_m);
  const Eigen::Vector2d dir = (s.to_m - s.from_m).normalized();
  const Eigen::Vector2d normal(-dir.y(), dir.x());
  const double length = (s.to_m - s.from_m).norm();
  for (std::size_t i = 0; i < cells.size(); ++i) {
    if (!active[i]) continue;
    const Eigen::Vector2d d = cells[i].centroid - s.from_m;
    if (d.dot(dir) >= 0.0 && d.dot(dir) <= length && std::abs(d.dot(normal)) <= band)
      retire(int(i));
  }
}

/// Hough accumulator over the cells still unexplained: votes per (angle, distance) bin.
class Hough {
 public:
  Hough(const std::vector<Cell>& cells, const WallExtractionParams& p) : cells_(cells) {
    angles_ = std::max(1, static_cast<int>(std::lround(180.0 / p.angle_step_deg)));
    for (const Cell& c : cells) origin_ += c.centroid;
    origin_ /= double(std::max<std::size_t>(1, cells.size()));
    for (const Cell& c : cells) reach_ = std::max(reach_, (c.centroid - origin_).norm());
    bin_m_ = p.line_tolerance_m;
    rhos_ = static_cast<int>(2.0 * reach_ / bin_m_) + 2;
    votes_.assign(std::size_t(angles_) * rhos_, 0);
    for (std::size_t i = 0; i < cells.size(); ++i) vote(int(i), +1);
  }
  void vote(int i, int sign) {
    for (int a = 0; a < angles_; ++a) votes_[std::size_t(a) * rhos_ + bin(a, i)] += sign;
  }
  /// The strongest line: (votes, unit normal, distance from the world origin).
  std::tuple<int, Eigen::Vector2d, double> peak() const {
    const auto best = std::max_element(votes_.begin(), votes_.end());
    const auto k = static_cast<int>(best - votes_.begin());
    const Eigen::Vector2d n = normal(k / rhos_);
    const double rho = ((k % rhos_) + 0.5) * bin_m_ - reach_;
    return {*best, n, rho + n.dot(origin_)};
  }

 private:
  Eigen::Vector2d normal(int a) const {
    const double theta = a * std::numbers::pi / angles_;
    return {std::cos(theta), std::sin(theta)};
  }
  int bin(int a, int i) const {
    const double rho = normal(a).dot(cells_[i].centroid - origin_);
    return std::clamp(static_cast<int>((rho + reach_) / bin_m_), 0, rhos_ - 1);
  }
  const std::vector<Cell>& cells_;
  Eigen::Vector2d origin_ = Eigen::Vector2d::Zero();
  double reach_ = 0.0, bin_m_ = 0.05;
  int angles_ = 180, rhos_ = 1;
  std::vector<int> votes_;
};

/// The active cells within tolerance of the line n . x = rho, refitted twice by TLS.
std::vector<int> lineInliers(const std::vector<Cell>& cells, const std::vector<char>& active,
                             Eigen::Vector2d n, double rho, double tolerance_m) {
  std::vector<int> in;
  for (int round = 0; round < 3; ++round) {
    in.clear();
    for (std::size_t i = 0; i < cells.size(); ++i)
      if (active[i] && std::abs(n.dot(cells[i].centroid) - rho) <= tolerance_m)
        in.push_back(int(i));
    if (in.size() < 2) return in;
    std::vector<Eigen::Vector2d> pts;
    for (int i : in) pts.push_back(cells[i].centroid);
    const auto [mean, dir] = fitLine(pts);
    n = {-dir.y(), dir.x()};
    rho = n.dot(mean);
  }
  return in;
}

/// The inliers split where consecutive cells along the line are more than max_gap apart.
std::vector<std::vector<int>> runsAlong(const std::vector<Cell>& cells, std::vector<int> in,
                                        const Eigen::Vector2d& n, double max_gap_m) {
  const Eigen::Vector2d dir(n.y(), -n.x());
  std::sort(in.begin(), in.end(),
            [&](int a, int b) { return cells[a].centroid.dot(dir) < cells[b].centroid.dot(dir); });
  std::vector<std::vector<int>> runs;
  for (std::size_t k = 0; k < in.size(); ++k) {
    const bool gap =
        k == 0 || (cells[in[k]].centroid - cells[in[k - 1]].centroid).dot(dir) > max_gap_m;
    if (gap) runs.emplace_back();
    runs.back().push_back(in[k]);
  }
  return runs;
}

double length(const WallSegment& s) {
  return (s.to_m - s.from_m).norm();
}

/// Connected groups of the cells no wall explained (8-neighbours, one empty cell bridged).
std::vector<std::vector<int>> clusters(const std::vector<Cell>& cells, std::vector<int> left) {
  std::sort(left.begin(), left.end());
  std::map<std::pair<int, int>, int> at;
  for (int i : left) at[{cells[i].index.x(), cells[i].index.y()}] = i;
  std::map<int, char> seen;
  std::vector<std::vector<int>> groups;
  for (int start : left) {
    if (seen[start]) continue;
    std::vector<int> group{start}, stack{start};
    seen[start] = 1;
    while (!stack.empty()) {
      const Eigen::Vector2i c = cells[stack.back()].index;
      stack.pop_back();
      for (int dx = -2; dx <= 2; ++dx)
        for (int dy = -2; dy <= 2; ++dy) {
          const auto it = at.find({c.x() + dx, c.y() + dy});
          if (it == at.end() || seen[it->second]) continue;
          seen[it->second] = 1;
          group.push_back(it->second);
          stack.push_back(it->second);
        }
    }
    groups.push_back(std::move(group));
  }
  return groups;
}

/// What no wall explained: compact groups become posts, elongated ones short walls; single
/// cells are dropped (a stray return seen twice).
void addClutter(const std::vector<Cell>& cells, const std::vector<int>& left,
                const WallExtractionParams& p, WallMap& map) {
  for (const std::vector<int>& group : clusters(cells, left)) {
    if (group.size() < 2) continue;
    WallSegment s = makeSegment(cells, group, p.cell_m);
    if (length(s) <= p.post_max_extent_m) {
      Eigen::Vector2d c = Eigen::Vector2d::Zero();
      for (int i : group) c += cells[i].centroid;
      c /= double(group.size());
      map.posts.push_back({c, std::max(0.5 * p.cell_m, 0.5 * length(s) - 0.5 * p.cell_m)});
    } else {
      map.clutter.push_back(s);
    }
  }
}

}  // namespace

WallMap extractWalls(const std::vector<MapPoint>& points, const WallExtractionParams& p) {
  WallMap map;
  const std::vector<Cell> cells = occupiedCells(points, p);
  map.occupied_cells = static_cast<int>(cells.size());
  if (cells.empty()) return map;
  std::vector<char> active(cells.size(), 1);
  std::vector<int> leftover;
  Hough hough(cells, p);
  const int min_cells = std::max(3, static_cast<int>(std::ceil(p.min_length_m / p.cell_m / 2)));
  auto retire = [&](int i) {
    active[i] = 0;
    hough.vote(i, -1);
  };
  for (;;) {
    const auto [votes, n, rho] = hough.peak();
    if (votes < min_cells) break;
    std::vector<int> in = lineInliers(cells, active, n, rho, p.line_tolerance_m);
    if (in.size() < 2) {  // the peak's cells lie off the refitted line: explain them elsewhere
      for (std::size_t i = 0; i < cells.size(); ++i)
        if (active[i] && std::abs(n.dot(cells[i].centroid) - rho) <= 0.5 * p.line_tolerance_m)
          in.push_back(int(i));
    }
    if (in.empty()) break;  // nothing left to explain on the strongest line
    for (const std::vector<int>& run : runsAlong(cells, in, n, p.max_gap_m)) {
      for (int i : run) retire(i);
      WallSegment s = run.size() >= 2 ? makeSegment(cells, run, p.cell_m) : WallSegment{};
      if (run.size() >= std::size_t(min_cells) && length(s) >= p.min_length_m) {
        map.cells_on_walls += s.cells;
        map.walls.push_back(s);
        retireFringe(cells, active, s, p, retire);
      } else {
        leftover.insert(leftover.end(), run.begin(), run.end());
      }
    }
  }
  for (std::size_t i = 0; i < cells.size(); ++i)
    if (active[i]) leftover.push_back(int(i));
  addClutter(cells, leftover, p, map);
  std::stable_sort(
      map.walls.begin(), map.walls.end(),
      [](const WallSegment& a, const WallSegment& b) { return length(a) > length(b); });
  return map;
}

sim::Wall faceAsWall(const WallSegment& face, const WallExtractionParams& p) {
  const Eigen::Vector2d shift = -0.5 * p.thickness_m * face.normal;
  return {face.from_m + shift, face.to_m + shift, p.thickness_m, 2.0, true};
}

sim::World wallsAsWorld(const WallMap& map, const WallExtractionParams& p) {
  sim::World world;
  world.name = "map";
  for (const WallSegment& s : map.walls) world.walls.push_back(faceAsWall(s, p));
  for (const WallSegment& s : map.clutter) world.walls.push_back(faceAsWall(s, p));
  for (const Post& post : map.posts)
    world.cylinders.push_back({post.center_m, post.radius_m, 1.0, true});
  return world;
}

}  // namespace slamprep::eval
