#include "slamprep/eval/formats/range_limit.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace slamprep::eval {
namespace {

constexpr double kBin = 0.01;          // m
constexpr std::size_t kBins = 100001;  // to 1 km, then the overflow bin
constexpr std::size_t kBinsPerMetre = 100;
constexpr double kNoReturnShare = 0.001;  // of the readings, at least
constexpr std::uint64_t kNoReturnMin = 10;
constexpr double kNoReturnTimesBelow = 50.0;

std::string number(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

}  // namespace

RangeHistogram::RangeHistogram() : bins_(kBins, 0) {}

std::size_t RangeHistogram::bin(double r) const {
  return std::min(kBins - 1, static_cast<std::size_t>(r / kBin));
}

std::uint64_t RangeHistogram::largestBinCount() const {
  return count_ == 0 ? 0 : bins_[bin(largest_)];
}

double RangeHistogram::meanBelowLargest() const {
  const std::size_t top = bin(largest_);
  const std::size_t from = top > kBinsPerMetre ? top - kBinsPerMetre : 0;
  if (top == from) return 0.0;
  std::uint64_t below = 0;
  for (std::size_t b = from; b < top; ++b) below += bins_[b];
  return double(below) / double(top - from);
}

void RangeHistogram::add(const LaserScan& scan) {
  if (std::isfinite(scan.range_max_m)) range_max_ = std::max(range_max_, scan.range_max_m);
  for (std::size_t i = 0; i < scan.size(); ++i) {
    if (!scan.valid(i)) continue;
    const double r = scan.ranges_m[i];
    ++bins_[bin(r)];
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

std::optional<NoReturnValue> noReturnValue(const RangeHistogram& h) {
  const std::uint64_t n = h.largestBinCount();
  const double below = h.meanBelowLargest();
  if (n < kNoReturnMin || double(n) < kNoReturnShare * double(h.count())) return std::nullopt;
  if (double(n) < kNoReturnTimesBelow * below) return std::nullopt;
  return NoReturnValue{h.largestReading(), n, below > 0 ? double(n) / below : 0.0};
}

std::size_t applyNoReturnValue(LaserScan& scan, double value_m) {
  std::size_t changed = 0;
  for (double& r : scan.ranges_m)
    if (std::isfinite(r) && r >= value_m - kBin) {
      r = std::numeric_limits<double>::infinity();
      ++changed;
    }
  scan.range_max_m = value_m;
  return changed;
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
  r.no_return = noReturnValue(h);
  if (r.no_return && max_range_m && r.no_return->value_m > *max_range_m) r.no_return.reset();
  return r;
}

std::string RangeReport::noReturnText() const {
  if (!no_return) return "";
  const std::string found =
      std::to_string(no_return->readings) + " readings (" +
      number(100.0 * double(no_return->readings) / double(readings)) + " %) at " +
      number(no_return->value_m) + " m, the largest reading" +
      (no_return->times_below > 0
           ? ", " + number(no_return->times_below) + "x the mean 1 cm bin of the metre below"
           : ", none in the metre below") +
      ": the sensor's value for no return";
  return found + (no_return_applied
                      ? ", made no return and range_max " + number(no_return->value_m) + " m"
                      : "; give --max-range " + number(no_return->value_m - 2 * kBin) +
                            " to make them no return");
}

std::string RangeReport::text() const {
  const std::string reach = "99.9 % of " + std::to_string(readings) + " readings under " +
                            number(p999_m) + " m, largest " + number(largest_m) + " m";
  const std::string tail = no_return ? "; " + noReturnText() : "";
  if (max_range_m)
    return number(*max_range_m) + " m (--max-range; the scans said " + number(range_max_m) +
           " m): " + std::to_string(cut) + " readings beyond it made no return; " + reach + tail;
  if (suspect)
    return "range_max " + number(range_max_m) + " m is not the sensor's: readings reach " +
           number(p999_m) + " m (" + reach + "); give --max-range" + tail;
  return number(range_max_m) + " m (the scans' range_max; " + reach + ")" + tail;
}

}  // namespace slamprep::eval
