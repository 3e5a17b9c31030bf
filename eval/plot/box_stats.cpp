#include <algorithm>
#include <cmath>

#include "eval/plot/plot.hpp"

namespace slamprep::eval::plot {
namespace {

// Type 7 quantile of an ascending, non-empty sample.
double quantile(const std::vector<double>& sorted, double p) {
  const double h = p * static_cast<double>(sorted.size() - 1);
  const auto below = static_cast<std::size_t>(std::floor(h));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  return sorted[below] + (h - static_cast<double>(below)) * (sorted[above] - sorted[below]);
}

}  // namespace

BoxStats boxStats(std::vector<double> sample) {
  std::erase_if(sample, [](double v) { return !std::isfinite(v); });
  BoxStats b;
  if (sample.empty()) return b;
  std::sort(sample.begin(), sample.end());
  b.n = sample.size();
  b.q1 = quantile(sample, 0.25);
  b.median = quantile(sample, 0.5);
  b.q3 = quantile(sample, 0.75);
  const double reach = 1.5 * (b.q3 - b.q1);
  b.whisker_low = b.q1;  // the box itself when no value lies below it within reach
  b.whisker_high = b.q3;
  for (const double v : sample) {
    if (v < b.q1 - reach || v > b.q3 + reach)
      b.outliers.push_back(v);
    else
      b.whisker_low = std::min(b.whisker_low, v), b.whisker_high = std::max(b.whisker_high, v);
  }
  return b;
}

}  // namespace slamprep::eval::plot
