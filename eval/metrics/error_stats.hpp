#pragma once
// Summary statistics of a set of errors (docs/metrics.md, "ErrorStats").

#include <cstddef>
#include <string>
#include <vector>

namespace slamprep::eval {

/// count, mean, rmse, median, std, min, max, p95 of a set of values. Percentiles interpolate
/// linearly between order statistics (numpy's default, Hyndman-Fan type 7); std is the
/// population standard deviation (divides by n, as numpy and evo do).
struct ErrorStats {
  bool ok = false;     ///< false for an empty set or a non-finite value (all figures 0 then)
  std::string reason;  ///< why !ok
  std::size_t count = 0;
  double mean = 0.0;
  double rmse = 0.0;
  double median = 0.0;
  double std = 0.0;
  double min = 0.0;
  double max = 0.0;
  double p95 = 0.0;
};

ErrorStats summarize(std::vector<double> values);

}  // namespace slamprep::eval
