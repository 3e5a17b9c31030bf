#pragma once
// Axis ticks: 1-2-5 steps on linear axes, decades (with 2..9 minor ticks) on log axes, and
// compact labels ("0.25", "1e-5", "10^{3}").

#include <string>
#include <vector>

#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval::plot {

/// One tick mark; minor ticks have no label.
struct Tick {
  double value = 0.0;  ///< position in data units
  std::string label;   ///< markup text, empty for minor ticks
  bool major = true;   ///< major ticks are longer, labelled and carry grid lines
};

/// Smallest step of the form {1, 2, 5} * 10^k that is >= raw_step (raw_step > 0).
double niceStep(double raw_step);

/// Labels `value` with as many decimals as `step` needs, or in scientific notation ("2.5e-5",
/// the mantissa with as many digits as `step` needs); a typographic minus sign; never "-0".
std::string formatTick(double value, double step, bool scientific);

/// Whether the labels of an axis showing `range` are written in scientific notation: when every
/// value is below 1e-3 or some value reaches 1e5 in magnitude.
bool wantsScientific(const Range& range);

/// Major ticks at multiples of a 1-2-5 step inside `range`: at most `max_major` of them, unless
/// that step leaves fewer than two, then the coarsest step that gives two.
std::vector<Tick> linearTicks(const Range& range, int max_major);

/// Decade ticks (every k-th decade if there are too many) with unlabelled minor ticks at 2..9.
/// When at most two decades fall inside, 1-2-5 values are labelled instead if they fit (then
/// 1..9 values), and a range too narrow for any of that falls back to linear ticks.
/// Requires 0 < range.min < range.max.
std::vector<Tick> logTicks(const Range& range, int max_major);

}  // namespace slamprep::eval::plot
