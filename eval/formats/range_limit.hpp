#pragma once
// The lidar's real reach. Cheap lidars publish a range_max that is not the sensor's (100 m while
// no reading exceeds 3.5-12 m); what lies beyond the reach is noise, not a return. --max-range M
// makes readings beyond M "no return" and sets range_max to M. Without it, the rule
// (docs/export.md, "Maximum range"): when the scans' range_max exceeds twice the 99.9th
// percentile of their finite readings, a note says so and the dataset records it. A value the
// sensor writes for "no return" (ACES's SICK 50.00 m) is found from the histogram: see
// RangeHistogram::noReturnValue.

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/core/laser_scan.hpp"

namespace slamprep::eval {

/// Finite readings in 1 cm bins up to 1 km (more: the last bin), so that the percentile of a
/// long bag's tens of millions of readings takes 800 KB, not the readings.
class RangeHistogram {
 public:
  RangeHistogram();
  /// The scan's finite readings within [range_min, range_max]; notes its range_max.
  void add(const LaserScan& scan);
  std::uint64_t count() const { return count_; }
  /// The q-quantile (0..1), to the bin's upper edge; 0 without readings.
  double quantile(double q) const;
  double largestReading() const { return largest_; }
  double largestRangeMax() const { return range_max_; }  ///< over the scans, finite ones
  /// Readings in the largest reading's 1 cm bin.
  std::uint64_t largestBinCount() const;
  /// The mean count of the 1 cm bins in the metre below the largest reading's bin.
  double meanBelowLargest() const;

 private:
  std::size_t bin(double r) const;

  std::vector<std::uint64_t> bins_;
  std::uint64_t count_ = 0;
  double largest_ = 0.0, range_max_ = 0.0;
};

/// A sensor's "no return" written as a range: the largest reading is one, when its 1 cm bin
/// holds at least 0.1 % of the readings (and 10) and 50 times the mean bin of the metre below
/// it. A far wall seen by many beams fills a few neighbouring bins, not one alone.
struct NoReturnValue {
  double value_m = 0.0;        ///< the largest reading
  std::uint64_t readings = 0;  ///< in its bin
  double times_below = 0.0;    ///< its bin's count over the mean bin of the metre below
};
std::optional<NoReturnValue> noReturnValue(const RangeHistogram& h);

/// Readings at or beyond `value_m` (to 1 cm) become +inf; range_max becomes value_m. Returns how
/// many were changed.
std::size_t applyNoReturnValue(LaserScan& scan, double value_m);

/// Readings beyond `max_range_m` become +inf (no return); range_max becomes max_range_m. Returns
/// how many readings were cut.
std::size_t applyMaxRange(LaserScan& scan, double max_range_m);

struct RangeReport {
  std::optional<double> max_range_m;  ///< --max-range, when given
  double range_max_m = 0.0;           ///< the scans' largest finite range_max (before --max-range)
  double p999_m = 0.0;                ///< 99.9th percentile of the finite readings
  double largest_m = 0.0;             ///< the largest finite reading
  std::uint64_t readings = 0;
  std::size_t cut = 0;                     ///< readings beyond --max-range made no return
  bool suspect = false;                    ///< range_max > 2 * p999 (without --max-range)
  std::optional<NoReturnValue> no_return;  ///< found, and not beyond --max-range
  bool no_return_applied = false;          ///< its readings were made no return
  std::string text() const;                ///< the summary line; the note when suspect
  std::string noReturnText() const;        ///< "" without a no-return value
};

/// The report of the histogram; `no_return` found but left to the caller to apply (a CARMEN
/// import makes its readings +inf and sets no_return_applied; a bag's report only names it: a
/// LaserScan marks no return itself, and --max-range cuts it).
RangeReport rangeReport(const RangeHistogram& h, std::optional<double> max_range_m,
                        std::size_t cut);

}  // namespace slamprep::eval
