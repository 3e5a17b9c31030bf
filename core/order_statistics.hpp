#pragma once
// Medians and quantiles of a sample, defined once for every library: type-7 quantiles (linear
// between order statistics, numpy's and R's default, Hyndman and Fan 1996), so a median of an
// even sample is the mean of its two middle values.

#include <vector>

namespace slamprep {

/// The q-quantile (q in [0, 1]) of a sample sorted ascending, type 7:
/// h = (n - 1) q, Q = x[floor h] + (h - floor h) (x[floor h + 1] - x[floor h]).
double quantileOfSorted(const std::vector<double>& sorted, double q);

/// The q-quantile of a sample in any order (sorts its copy); 0 for an empty sample.
double quantile(std::vector<double> sample, double q);

/// quantile(sample, 0.5).
double median(std::vector<double> sample);

/// The median of the differences of consecutive values (the period of a stream from its
/// stamps); 0 for fewer than two values.
double medianSpacing(const std::vector<double>& values);

}  // namespace slamprep
