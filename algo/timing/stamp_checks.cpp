#include "slamprep/algo/timing/stamp_checks.hpp"

#include <algorithm>
#include <cmath>

#include "slamprep/core/order_statistics.hpp"

namespace slamprep::algo {
namespace {

/// Steady steps, or scan steps, fewer than this decide nothing.
constexpr std::size_t kMinSteps = 30;

double rms(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x * x;
  return v.empty() ? 0.0 : std::sqrt(sum / double(v.size()));
}

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

std::optional<ScanTimeCheck> checkScanTimes(const std::vector<ScanRecord>& scans) {
  std::vector<double> steps, started, ended;  // step k: scan k's stamp to scan k + 1's
  for (std::size_t k = 0; k + 1 < scans.size(); ++k) {
    const LaserScan &a = scans[k].scan, &b = scans[k + 1].scan;
    if (!(a.scan_time_s > 0.0 && b.scan_time_s > 0.0)) continue;
    steps.push_back(b.stamp_s - a.stamp_s);
    started.push_back(a.scan_time_s);
    ended.push_back(b.scan_time_s);
  }
  if (steps.size() < kMinSteps) return std::nullopt;
  double mean = 0.0;
  for (double s : steps) mean += s / double(steps.size());
  std::vector<double> about_mean, about_started, about_ended;
  for (std::size_t k = 0; k < steps.size(); ++k) {
    about_mean.push_back(steps[k] - mean);
    about_started.push_back(steps[k] - started[k]);
    about_ended.push_back(steps[k] - ended[k]);
  }
  return ScanTimeCheck{steps.size(), std::min(rms(about_started), rms(about_ended)),
                       rms(about_mean)};
}

}  // namespace slamprep::algo
