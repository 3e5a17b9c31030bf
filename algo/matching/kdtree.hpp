#pragma once
// A 2D kd-tree over a point set (nanoflann): nearest and k-nearest neighbours.

#include <Eigen/Core>
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "slamprep/core/laser_scan.hpp"

namespace slamprep::algo {

/// One neighbour: its index in the tree's point set and its squared distance to the query.
struct Neighbor {
  std::size_t index = 0;
  double distance_sq_m2 = 0.0;
};

/// Owns a copy of its points; movable, not copyable (the index points into the copy).
class KdTree2 {
 public:
  explicit KdTree2(Points2 points);
  ~KdTree2();
  KdTree2(KdTree2&&) noexcept;
  KdTree2& operator=(KdTree2&&) noexcept;
  KdTree2(const KdTree2&) = delete;
  KdTree2& operator=(const KdTree2&) = delete;

  const Points2& points() const;
  std::size_t size() const { return points().size(); }

  /// The nearest point to `query`; nullopt for an empty tree.
  std::optional<Neighbor> nearest(const Eigen::Vector2d& query) const;
  /// The same, searching only for points closer than point `hint` (a likely answer, e.g. last
  /// iteration's): exact, and much faster when the hint is good. `hint` must be < size().
  std::optional<Neighbor> nearest(const Eigen::Vector2d& query, std::size_t hint) const;
  /// The min(k, size) nearest points, closest first.
  std::vector<Neighbor> nearestK(const Eigen::Vector2d& query, std::size_t k) const;
  /// The same without allocating: writes min(k, size, kMaxInto) neighbours to `out`, returns
  /// how many.
  static constexpr std::size_t kMaxInto = 16;
  std::size_t nearestInto(const Eigen::Vector2d& query, std::size_t k, Neighbor* out) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace slamprep::algo
