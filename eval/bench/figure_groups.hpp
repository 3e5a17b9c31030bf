#pragma once
// What every suite figure shares: the groups of a summary (one condition each: scenario and
// sweep values, over its seeds) named in words, one colour and marker per method in every
// figure, and a statistic with the number of seeds behind it. Figures never pool groups.

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/eval/bench/suite_summary.hpp"
#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval {

/// "Circle arc", "Circle at 0.5 m/s, lidar 5 Hz", "every fault": what sets the group apart from
/// the others of `groups` (its scenario when they differ, its sweep values), in words.
std::string conditionLabel(const SummaryGroup& group, const std::vector<SummaryGroup>& groups);

/// The trials of one group, one metric path -> value map per seed (rows of trials.csv).
using TrialRows = std::vector<std::map<std::string, double>>;

/// From this many seeds on, a group's spread is drawn as box plots of the per-seed values
/// (quartiles, median, Tukey whiskers) instead of a mean with min..max whiskers, which with many
/// seeds span the rare extremes and hide the distribution.
inline constexpr int kMinSeedsForBoxes = 10;

/// "quartiles, median, whiskers to 1.5 IQR over 100 seeds": what a box plot of a group shows.
std::string boxSeedsNote(int seeds);

/// "1 seed" / "mean, min to max over 5 seeds": what the dots and whiskers of a group show.
std::string seedsNote(int seeds);

/// Appends metrics[path]'s mean (times `scale`) to `s` with a whisker from the smallest to the
/// largest seed's value when `seeds` >= 2 (a 1σ bar would cross zero on the log axes), none
/// with one seed.
void pushMeanWithSpread(plot::Series& s, double x, const SummaryMetrics& metrics,
                        const std::string& path, int seeds, double scale = 1.0);

/// A statistic of a metric (`&MetricStats::mean`); NaN when absent.
double statOf(const SummaryMetrics& metrics, const std::string& path, double MetricStats::*stat);

/// The trials of a group as a seed count.
int seedsOf(const SummaryGroup& group);

/// Calibration methods with an "ok" rate in any group, in first-seen order.
std::vector<std::string> calibrationMethodsIn(const std::vector<SummaryGroup>& groups);
/// De-skew methods with a mean point error in any group, in first-seen order.
std::vector<std::string> deskewMethodsIn(const std::vector<SummaryGroup>& groups);

/// Every calibration method / every de-skew method but the oracle, in the library's order: the
/// `all` a method's colour and marker come from, the same in every suite whichever methods it ran.
const std::vector<std::string>& calibrationPalette();
const std::vector<std::string>& deskewPalette();

/// The same colour and marker for a method in every figure: its place in `all`.
plot::Color methodColor(const std::vector<std::string>& all, const std::string& method);
plot::Marker methodMarker(const std::vector<std::string>& all, const std::string& method);

/// Dots (with min..max whiskers when seeds >= 2) of one method, at categorical x positions.
plot::Series methodDots(const std::vector<std::string>& all, const std::string& method);

/// When every group's scenario is one file of a series, `<stem><number>.yaml` with one stem
/// (circle_v0.25, circle_v0.5, ...), the numbers; nullopt otherwise (unrelated scenarios,
/// which must not be joined by lines).
std::optional<std::vector<double>> scenarioSeries(const std::vector<SummaryGroup>& groups);

/// "lidar 5 Hz" before "lidar 10 Hz": numbers inside the labels compare by value.
bool naturalLess(const std::string& a, const std::string& b);

/// The seeds behind every group when they are equal ("mean, min to max over 5 seeds"), else "".
std::string commonSeedsNote(const std::vector<SummaryGroup>& groups);

/// Sweep values of a group other than `axis`, as a label ("lidar 5 Hz"); "" when none.
std::string otherSweepLabel(const SummaryGroup& group, const std::string& axis);

}  // namespace slamprep::eval
