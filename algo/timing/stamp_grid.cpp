#include "slamprep/algo/timing/stamp_grid.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "slamprep/core/order_statistics.hpp"

namespace slamprep::algo {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Sample i's grid index: its stamp less the grid's phase there, in periods. The phase is the
// circular mean of t mod T over the samples around i, which jitter below T/2 cannot bias by a
// whole period; unwrapped from sample to sample, it follows a slightly wrong T as a slow drift.
std::vector<long> gridIndices(std::span<const double> t, double period, std::size_t window) {
  const std::size_t n = t.size(), h = window / 2;
  std::vector<double> c(n + 1, 0.0), s(n + 1, 0.0);  // prefix sums of the phasors
  for (std::size_t i = 0; i < n; ++i) {
    const double a = kTwoPi * std::fmod(t[i] - t[0], period) / period;
    c[i + 1] = c[i] + std::cos(a);
    s[i + 1] = s[i] + std::sin(a);
  }
  std::vector<long> k(n);
  double previous = 0.0;  // unwrapped phase of the previous sample's window, in periods
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t lo = i > h ? i - h : 0, hi = std::min(n, i + h + 1);
    const double wrapped = std::atan2(s[hi] - s[lo], c[hi] - c[lo]) / kTwoPi;
    const double phase = wrapped + std::round(previous - wrapped);
    previous = phase;
    k[i] = std::lround((t[i] - t[0]) / period - phase);
  }
  return k;
}

// Least-squares line t = t[ref] + mt + slope (k - k[ref] - mk) through samples [lo, hi), in
// offsets from sample ref so that large stamps and indices lose no digits.
struct Line {
  double mk = 0.0, mt = 0.0, slope = 0.0;
};
Line fitLine(std::span<const double> t, const std::vector<long>& k, std::size_t lo, std::size_t hi,
             std::size_t ref) {
  Line line;
  for (std::size_t j = lo; j < hi; ++j) line.mk += k[j] - k[ref], line.mt += t[j] - t[ref];
  line.mk /= static_cast<double>(hi - lo), line.mt /= static_cast<double>(hi - lo);
  double skk = 0, skt = 0;
  for (std::size_t j = lo; j < hi; ++j) {
    const double dk = k[j] - k[ref] - line.mk;
    skk += dk * dk;
    skt += dk * (t[j] - t[ref] - line.mt);
  }
  line.slope = skk > 0 ? skt / skk : 0.0;
  return line;
}

// The grid time of sample i: the line through the samples around i, at k[i].
std::vector<double> localLineFit(std::span<const double> t, const std::vector<long>& k,
                                 std::size_t window) {
  const std::size_t n = t.size(), h = window / 2;
  std::vector<double> grid(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Line line = fitLine(t, k, i > h ? i - h : 0, std::min(n, i + h + 1), i);
    grid[i] = t[i] + line.mt - line.slope * line.mk;
  }
  return grid;
}

// The slope of the line through all samples: the mean period once the indices are known.
double fittedPeriod(std::span<const double> t, const std::vector<long>& k) {
  return fitLine(t, k, 0, t.size(), 0).slope;
}

// Indices moved to the nearest point of the local line through the samples (a sharper phase
// than the circular mean's), then each pair that shares a grid point split: of the two, the
// sample closer to its neighbouring point moves there. Jitter cut just below half a period
// (the simulated stamp_jitter fault) puts such pairs within a few percent of a period.
void refineIndices(std::span<const double> t, std::vector<long>& k, double period,
                   std::size_t window) {
  const std::vector<double> grid = localLineFit(t, k, window);
  for (std::size_t i = 0; i < t.size(); ++i) k[i] += std::lround((t[i] - grid[i]) / period);
  for (std::size_t i = 1; i < t.size(); ++i) {
    if (k[i] > k[i - 1]) continue;
    const double ahead = std::abs(t[i] - grid[i] - (k[i - 1] + 1 - k[i]) * period);
    const bool can_go_back = i < 2 || k[i - 1] - 1 > k[i - 2];
    const double back = std::abs(t[i - 1] - grid[i - 1] - (k[i] - 1 - k[i - 1]) * period);
    if (can_go_back && back < ahead)
      k[i - 1] = k[i] - 1;
    else
      k[i] = k[i - 1] + 1;
  }
}

StampGrid leftAlone(std::span<const double> t, std::string reason) {
  StampGrid out;
  out.stamps.assign(t.begin(), t.end());
  out.reason = std::move(reason);
  return out;
}

}  // namespace

StampGrid fitStampGrid(std::span<const double> t, const StampGridParams& params) {
  if (t.size() < 8) return leftAlone(t, "fewer than 8 stamps");
  double period = medianSpacing({t.begin(), t.end()});
  if (!(period > 0.0)) return leftAlone(t, "stamps do not increase");
  // The median step misses the period by ~0.1 % under jitter, which over hundreds of samples
  // shifts the phase at the ends of the stream; a second pass with the fitted period does not.
  std::vector<long> k = gridIndices(t, period, params.window);
  period = fittedPeriod(t, k);
  if (!(period > 0.0)) return leftAlone(t, "stamps do not increase");
  k = gridIndices(t, period, params.window);
  refineIndices(t, k, period, params.window);
  for (std::size_t i = 1; i < k.size(); ++i)
    if (k[i] <= k[i - 1]) return leftAlone(t, "two stamps fall on one grid point");
  const std::vector<double> grid = localLineFit(t, k, params.window);

  StampGrid out;
  double sum_sq = 0.0;
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double r = t[i] - grid[i];
    sum_sq += r * r;
    out.residual_max_s = std::max(out.residual_max_s, std::abs(r));
  }
  out.residual_rms_s = std::sqrt(sum_sq / t.size());
  out.period_s = (grid.back() - grid.front()) / (k.back() - k.front());
  out.missing_samples = static_cast<std::size_t>(k.back() - k.front()) + 1 - t.size();
  for (std::size_t i = 1; i < grid.size(); ++i)
    if (!(grid[i] > grid[i - 1])) return leftAlone(t, "the fitted grid does not increase");
  if (out.residual_rms_s <= params.min_rms_s) {
    out.stamps.assign(t.begin(), t.end());
    out.reason = "regular already";
  } else if (out.residual_rms_s > params.max_rms_fraction * out.period_s) {
    out.stamps.assign(t.begin(), t.end());
    out.reason = "not a constant-rate stream";
  } else {
    out.stamps = grid;
    out.applied = true;
  }
  return out;
}

double streamPeriod(std::span<const double> stamps, const StampGridParams& params) {
  const StampGrid grid = fitStampGrid(stamps, params);
  if (grid.applied || grid.reason == "regular already") return grid.period_s;
  if (stamps.size() < 2) return 0.0;
  return medianSpacing({stamps.begin(), stamps.end()});
}

}  // namespace slamprep::algo
