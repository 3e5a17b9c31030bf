#include "slamprep/core/order_statistics.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

namespace slamprep {

double quantileOfSorted(const std::vector<double>& sorted, double q) {
  assert(!sorted.empty() && q >= 0.0 && q <= 1.0);
  const double h = static_cast<double>(sorted.size() - 1) * q;
  const auto below = static_cast<std::size_t>(std::floor(h));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (h - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

// Two order statistics in O(n): the one at floor(h) in place, the next the least above it.
double quantile(std::vector<double> sample, double q) {
  if (sample.empty()) return 0.0;
  assert(q >= 0.0 && q <= 1.0);
  const double h = static_cast<double>(sample.size() - 1) * q;
  const auto below = static_cast<std::size_t>(std::floor(h));
  const auto at = sample.begin() + static_cast<std::ptrdiff_t>(below);
  std::nth_element(sample.begin(), at, sample.end());
  if (below + 1 >= sample.size()) return *at;
  const double next = *std::min_element(at + 1, sample.end());
  return *at + (h - static_cast<double>(below)) * (next - *at);
}

double median(std::vector<double> sample) {
  return quantile(std::move(sample), 0.5);
}

double medianSpacing(const std::vector<double>& values) {
  if (values.size() < 2) return 0.0;
  std::vector<double> spacing(values.size() - 1);
  for (std::size_t k = 1; k < values.size(); ++k) spacing[k - 1] = values[k] - values[k - 1];
  return median(std::move(spacing));
}

}  // namespace slamprep
