#include <algorithm>
#include <cmath>

#include "slamprep/core/order_statistics.hpp"
#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot {
namespace {}  // namespace

BoxStats boxStats(std::vector<double> sample) {
  std::erase_if(sample, [](double v) { return !std::isfinite(v); });
  BoxStats b;
  if (sample.empty()) return b;
  std::sort(sample.begin(), sample.end());
  b.n = sample.size();
  b.q1 = quantileOfSorted(sample, 0.25);
  b.median = quantileOfSorted(sample, 0.5);
  b.q3 = quantileOfSorted(sample, 0.75);
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
