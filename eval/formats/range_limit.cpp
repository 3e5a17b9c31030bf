#include "slamprep/eval/formats/range_limit.hpp"

#include <cmath>
#include <sstream>

namespace slamprep::eval {
namespace {

constexpr double kBin = 0.01;          // m
constexpr std::size_t kBins = 100001;  // to 1 km, then the overflow bin

std::string number(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

}  // namespace

RangeHistogram::RangeHistogram() : bins_(kBins, 0) {}

void RangeHistogram::add(const LaserScan& scan) {
  if (std::isfinite(scan.range_max_m)) range_max_ = std::max(range_max_, scan.range_max_m);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.valid(i)) continue;
    const double r = scan.ranges_m[i];
    ++bins_[std::min(kBins - 1, static_cast<std::size_t>(r / kBin))];
    ++count_;
    largest_ = std::max(largest_, r);
  }
}

double RangeHistogram::quantile(double q) const {
  if (count_ == 0) return 0.0;
  const auto rank = static_cast<std::uint64_t>(std::ceil(q * double(count_)));
  std::uint64_t seen = 0;
  for (std::size_t b = 0; b < kBins; ++b) {
    seen += bins_[b];
    if (seen >= rank && seen > 0) return std::min(largest_, (b + 1) * kBin);
  }
  return largest_;
}

std::size_t applyMaxRange(LaserScan& scan, double max_range_m) {
  std::size_t cut = 0;
  for (double& r : scan.ranges_m)
    if (std::isfinite(r) && r > max_range_m) {
      r = std::numeric_limits<double>::infinity();
      ++cut;
    }
  scan.range_max_m = max_range_m;
  return cut;
}

RangeReport rangeReport(const RangeHistogram& h, std::optional<double> max_range_m,
                        std::size_t cut) {
  RangeReport r;
  r.max_range_m = max_range_m;
  r.range_max_m = h.largestRangeMax();
  r.p999_m = h.quantile(0.999);
  r.largest_m = h.largestReading();
  r.readings = h.count();
  r.cut = cut;
  r.suspect = !max_range_m && r.readings > 0 && r.range_max_m > 2 * r.p999_m;
  return r;
}

std::string RangeReport::text() const {
  const std::string reach = "99.9 % of " + std::to_string(readings) + " readings under " +
                            number(p999_m) + " m, largest " + number(largest_m) + " m";
  if (max_range_m)
    return number(*max_range_m) + " m (--max-range; the scans said " + number(range_max_m) +
           " m): " + std::to_string(cut) + " readings beyond it made no return; " + reach;
  if (suspect)
    return "range_max " + number(range_max_m) + " m is not the sensor's: readings reach " +
           number(p999_m) + " m (" + reach + "); give --max-range";
  return number(range_max_m) + " m (the scans' range_max; " + reach + ")";
}

}  // namespace slamprep::eval
