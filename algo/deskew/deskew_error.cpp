#include "algo/deskew/deskew_error.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

namespace slamprep::algo {

void DeskewErrorAccumulator::add(const std::vector<std::optional<Eigen::Vector2d>>& p_ref,
                                 const std::vector<std::optional<Eigen::Vector2d>>& p_true) {
  assert(p_ref.size() == p_true.size());
  const std::size_t n = std::min(p_ref.size(), p_true.size());
  for (std::size_t i = 0; i < n; ++i)
    if (p_ref[i] && p_true[i]) distances_m_.push_back((*p_ref[i] - *p_true[i]).norm());
}

DeskewError DeskewErrorAccumulator::summary() const {
  DeskewError e;
  e.beams = distances_m_.size();
  if (e.beams == 0) return e;
  double sum = 0.0, sum_sq = 0.0;
  for (double d : distances_m_) sum += d, sum_sq += d * d, e.max_m = std::max(e.max_m, d);
  e.mean_m = sum / e.beams;
  e.rms_m = std::sqrt(sum_sq / e.beams);
  std::vector<double> sorted = distances_m_;
  const std::size_t rank = static_cast<std::size_t>(std::ceil(0.95 * e.beams)) - 1;
  std::nth_element(sorted.begin(), sorted.begin() + rank, sorted.end());
  e.p95_m = sorted[rank];
  return e;
}

DeskewError deskewError(const std::vector<std::optional<Eigen::Vector2d>>& p_ref,
                        const std::vector<std::optional<Eigen::Vector2d>>& p_true) {
  DeskewErrorAccumulator acc;
  acc.add(p_ref, p_true);
  return acc.summary();
}

}  // namespace slamprep::algo
