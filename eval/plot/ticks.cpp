#include "slamprep/eval/plot/ticks.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdio>
#include <utility>

namespace slamprep::eval::plot {
namespace {

constexpr const char* kMinus = "\xE2\x88\x92";  // U+2212, the typographic minus sign
constexpr double kRelTol = 1e-9;                // ticks this close to a range end still count

std::string withMinus(std::string text) {
  if (!text.empty() && text.front() == '-') text.replace(0, 1, kMinus);
  return text;
}

std::string fixed(double value, int decimals) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.*f", decimals, value);
  return buffer;
}

std::string stripZeros(std::string text) {
  if (text.find('.') == std::string::npos) return text;
  while (text.back() == '0') text.pop_back();
  if (text.back() == '.') text.pop_back();
  return text;
}

/// Decimals needed to tell multiples of `step` apart.
int decimalsFor(double step) {
  return std::max(0, static_cast<int>(-std::floor(std::log10(step) + kRelTol)));
}

std::string scientific(double value, double step) {
  int exponent = static_cast<int>(std::floor(std::log10(std::abs(value)) + kRelTol));
  const int step_exponent = static_cast<int>(std::floor(std::log10(step) + kRelTol));
  const int digits = std::max(0, exponent - step_exponent);
  std::string mantissa = fixed(value / std::pow(10.0, exponent), digits);
  if (mantissa == "10" || mantissa.rfind("10.", 0) == 0 || mantissa.rfind("-10", 0) == 0) {
    ++exponent;  // 9.99 rounded up to 10.0
    mantissa = fixed(value / std::pow(10.0, exponent), std::max(0, digits - 1));
  }
  std::string text = withMinus(stripZeros(mantissa)) + "e";
  if (exponent < 0) text += kMinus;
  return text + std::to_string(std::abs(exponent));
}

/// Number of multiples of step inside range, and the first one's index.
std::pair<long long, long long> multiplesInside(const Range& range, double step) {
  const auto first = static_cast<long long>(std::ceil(range.min / step - kRelTol));
  const auto last = static_cast<long long>(std::floor(range.max / step + kRelTol));
  return {first, last - first + 1};
}

bool inside(double value, const Range& range) {
  const double tolerance = kRelTol * std::max(std::abs(range.min), std::abs(range.max));
  return value >= range.min - tolerance && value <= range.max + tolerance;
}

}  // namespace

double niceStep(double raw_step) {
  assert(raw_step > 0.0 && std::isfinite(raw_step));
  const double decade = std::pow(10.0, std::floor(std::log10(raw_step)));
  for (const double factor : {1.0, 2.0, 5.0, 10.0}) {
    if (factor * decade >= raw_step * (1.0 - kRelTol)) return factor * decade;
  }
  return 10.0 * decade;
}

bool wantsScientific(const Range& range) {
  const double largest = std::max(std::abs(range.min), std::abs(range.max));
  return largest >= 1e5 || largest < 1e-3;
}

std::string formatTick(double value, double step, bool use_scientific) {
  assert(step > 0.0);
  if (std::abs(value) < step * 1e-6) return use_scientific ? "0" : fixed(0.0, decimalsFor(step));
  if (use_scientific) return scientific(value, step);
  return withMinus(fixed(value, decimalsFor(step)));
}

std::vector<Tick> linearTicks(const Range& range, int max_major) {
  assert(range.max > range.min);
  max_major = std::max(2, max_major);
  double step = niceStep((range.max - range.min) / max_major);
  while (multiplesInside(range, step).second > max_major) step = niceStep(step * 1.5);
  for (int i = 0; i < 3 && multiplesInside(range, step).second < 2; ++i) {
    step = niceStep(step / 2.6);  // one 1-2-5 level down: 10 -> 5 -> 2 -> 1
  }
  const bool sci = wantsScientific(range);
  const auto [first, count] = multiplesInside(range, step);
  std::vector<Tick> ticks;
  for (long long i = 0; i < count; ++i) {
    double value = static_cast<double>(first + i) * step;
    if (std::abs(value) < step * 1e-9) value = 0.0;
    ticks.push_back({value, formatTick(value, step, sci), true});
  }
  return ticks;
}

namespace {

std::vector<Tick> decadeTicks(int k0, int k1, double lo, double hi, int max_major) {
  const int decades = k1 - k0 + 1;
  int every = 1;
  for (const int d : {1, 2, 3, 4, 5, 10, 20, 25, 50, 100}) {
    every = d;
    if ((decades + d - 1) / d <= max_major) break;
  }
  std::vector<Tick> ticks;
  for (int k = k0; k <= k1; ++k) {
    const bool major = ((k % every) + every) % every == 0;
    const std::string label = major ? "10^{" + withMinus(std::to_string(k)) + "}" : "";
    ticks.push_back({std::pow(10.0, k), label, major});
  }
  if (every == 1 && hi - lo <= 10.0) {  // minor ticks at 2..9 x 10^k
    const Range range{std::pow(10.0, lo), std::pow(10.0, hi)};
    for (int k = k0 - 1; k <= k1; ++k) {
      for (int m = 2; m <= 9; ++m) {
        const double value = m * std::pow(10.0, k);
        if (inside(value, range)) ticks.push_back({value, "", false});
      }
    }
  }
  std::sort(ticks.begin(), ticks.end(),
            [](const Tick& a, const Tick& b) { return a.value < b.value; });
  return ticks;
}

/// Ticks at m * 10^k; `labelled(m)` says which mantissas are major.
template <typename Labelled>
std::vector<Tick> mantissaTicks(const Range& range, Labelled labelled) {
  const bool sci = wantsScientific(range);
  const int k0 = static_cast<int>(std::floor(std::log10(range.min))) - 1;
  const int k1 = static_cast<int>(std::ceil(std::log10(range.max)));
  std::vector<Tick> ticks;
  for (int k = k0; k <= k1; ++k) {
    const double decade = std::pow(10.0, k);
    for (int m = 1; m <= 9; ++m) {
      const double value = m * decade;
      if (!inside(value, range)) continue;
      const bool major = labelled(m);
      ticks.push_back({value, major ? formatTick(value, decade, sci) : "", major});
    }
  }
  return ticks;
}

long long countMajor(const std::vector<Tick>& ticks) {
  return std::count_if(ticks.begin(), ticks.end(), [](const Tick& t) { return t.major; });
}

}  // namespace

std::vector<Tick> logTicks(const Range& range, int max_major) {
  assert(range.min > 0.0 && range.max > range.min);
  max_major = std::max(2, max_major);
  const double lo = std::log10(range.min);
  const double hi = std::log10(range.max);
  const int k0 = static_cast<int>(std::ceil(lo - kRelTol));
  const int k1 = static_cast<int>(std::floor(hi + kRelTol));
  const int decades = k1 - k0 + 1;
  auto fits = [&](const std::vector<Tick>& t) {
    return countMajor(t) >= 2 && countMajor(t) <= max_major;
  };
  if (decades >= 3) return decadeTicks(k0, k1, lo, hi, max_major);
  // Two decade labels or fewer say little about the scale: label 1, 2, 5 when they fit.
  auto ticks = mantissaTicks(range, [](int m) { return m == 1 || m == 2 || m == 5; });
  if (fits(ticks)) return ticks;
  if (decades == 2) return decadeTicks(k0, k1, lo, hi, max_major);
  // Sparser mantissas before linear steps: linear labels on a log axis bunch up at the top.
  for (const auto& pair : {std::pair{1, 3}, std::pair{1, 5}, std::pair{2, 5}}) {
    ticks = mantissaTicks(range, [&](int m) { return m == pair.first || m == pair.second; });
    if (fits(ticks)) return ticks;
  }
  ticks = mantissaTicks(range, [](int) { return true; });
  if (fits(ticks)) return ticks;
  return linearTicks(range, max_major);
}

}  // namespace slamprep::eval::plot
