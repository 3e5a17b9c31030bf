#include "slamprep/eval/metrics/error_stats.hpp"

#include <algorithm>
#include <cmath>

#include "slamprep/core/order_statistics.hpp"

namespace slamprep::eval {

ErrorStats summarize(std::vector<double> values) {
  ErrorStats s;
  if (values.empty()) {
    s.reason = "no values";
    return s;
  }
  for (std::size_t i = 0; i < values.size(); ++i)
    if (!std::isfinite(values[i])) {
      s.reason = "value " + std::to_string(i) + " is not finite";
      return s;
    }
  std::sort(values.begin(), values.end());
  const double n = static_cast<double>(values.size());
  double sum = 0.0, sum_sq = 0.0;
  for (double v : values) {
    sum += v;
    sum_sq += v * v;
  }
  s.ok = true;
  s.count = values.size();
  s.mean = sum / n;
  s.rmse = std::sqrt(sum_sq / n);
  // Two-pass variance: sum (v - mean)^2 / n, stable when mean >> std.
  double var = 0.0;
  for (double v : values) var += (v - s.mean) * (v - s.mean);
  s.std = std::sqrt(var / n);
  s.min = values.front();
  s.max = values.back();
  s.median = quantileOfSorted(values, 0.5);
  s.p95 = quantileOfSorted(values, 0.95);
  return s;
}

}  // namespace slamprep::eval
