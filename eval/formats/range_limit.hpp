#pragma once
// The lidar's real reach. Cheap lidars publish a range_max that is not the sensor's (100 m while
// no reading exceeds 3.5-12 m); what lies beyond the reach is noise, not a return. --max-range M
// makes readings beyond M "no return" and sets range_max to M. Without it, the rule
// (docs/export.md, "Maximum range"): when the scans' range_max exceeds twice the 99.9th
// percentile of their finite readings, a note says so and the dataset records it.

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

 private:
  std::vector<std::uint64_t> bins_;
  std::uint64_t count_ = 0;
  double largest_ = 0.0, range_max_ = 0.0;
};

/// Readings beyond `max_range_m` become +inf (no return); range_max becomes max_range_m. Returns
/// how many readings were cut.
std::size_t applyMaxRange(LaserScan& scan, double max_range_m);

struct RangeReport {
  std::optional<double> max_range_m;  ///< --max-range, when given
  double range_max_m = 0.0;           ///< the scans' largest finite range_max (before --max-range)
  double p999_m = 0.0;                ///< 99.9th percentile of the finite readings
  double largest_m = 0.0;             ///< the largest finite reading
  std::uint64_t readings = 0;
  std::size_t cut = 0;       ///< readings beyond --max-range made no return
  bool suspect = false;      ///< range_max > 2 * p999 (without --max-range)
  std::string text() const;  ///< the summary line; the note when suspect
};

RangeReport rangeReport(const RangeHistogram& h, std::optional<double> max_range_m,
                        std::size_t cut);

}  // namespace slamprep::eval
