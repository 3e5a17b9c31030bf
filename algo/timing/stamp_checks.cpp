#include "slamprep/algo/timing/stamp_checks.hpp"

#include <algorithm>
#include <cmath>

#include "slamprep/core/order_statistics.hpp"

namespace slamprep::algo {
namespace {

/// Steady steps fewer than this decide nothing.
constexpr std::size_t kMinSteps = 30;

}  // namespace

std::optional<double> tickStampErrorBound(const std::vector<EncoderSample>& e) {
  std::vector<double> t;
  for (const EncoderSample& s : e) t.push_back(s.stamp_s);
  if (t.size() < 2 * kMinSteps) return std::nullopt;
  const double T = medianSpacing(t);
  std::vector<double> miss;
  for (const auto ticks : {&EncoderSample::ticks_left, &EncoderSample::ticks_right})
    for (std::size_t i = 4; i + 3 < e.size(); ++i) {
      const auto c = [&](std::size_t k) { return double(e[k].*ticks); };
      const double rate = (c(i + 3) - c(i - 4)) / (t[i + 3] - t[i - 4]);
      const double before = (c(i - 1) - c(i - 4)) / (t[i - 1] - t[i - 4]);
      const double after = (c(i + 3) - c(i)) / (t[i + 3] - t[i]);
      if (std::abs(rate * T) < 20.0 || std::abs(before - after) > 0.1 * std::abs(rate)) continue;
      miss.push_back((c(i) - c(i - 1) - rate * (t[i] - t[i - 1])) / (rate * T));
    }
  if (miss.size() < kMinSteps) return std::nullopt;
  for (double& m : miss) m = std::abs(m);
  return T * 1.4826 * median(std::move(miss)) / std::sqrt(2.0);  // Eq. 1
}

}  // namespace slamprep::algo
