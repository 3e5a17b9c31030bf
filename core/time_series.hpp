#pragma once
// A time-stamped series with strictly increasing stamps, bracketing lookup and interpolation.

#include <algorithm>
#include <cassert>
#include <optional>
#include <vector>

#include "slamprep/core/se2.hpp"

namespace slamprep {

template <typename T>
struct Stamped {
  double stamp_s = 0.0;
  T value{};
};

/// How a value type interpolates; specialised for SE2 (geodesic), linear for arithmetic types.
template <typename T>
T interpolateValue(const T& a, const T& b, double fraction) {
  return a + (b - a) * fraction;
}
template <>
inline SE2 interpolateValue<SE2>(const SE2& a, const SE2& b, double fraction) {
  return interpolate(a, b, fraction);
}

/// Samples i and i+1 around a time, and where the time falls between them.
struct Bracket {
  std::size_t index = 0;  ///< stamp[index] <= t <= stamp[index + 1]
  double fraction = 0.0;  ///< (t - stamp[index]) / (stamp[index + 1] - stamp[index])
};

template <typename T>
class TimeSeries {
 public:
  TimeSeries() = default;

  /// Appends a sample; stamps must increase strictly (checked by the readers for user data).
  void push_back(double stamp_s, const T& value) {
    assert(samples_.empty() || stamp_s > samples_.back().stamp_s);
    samples_.push_back({stamp_s, value});
  }

  /// Reserves room for n samples (writers that know the count avoid reallocating).
  void reserve(std::size_t n) { samples_.reserve(n); }
  std::size_t size() const { return samples_.size(); }
  bool empty() const { return samples_.empty(); }
  const Stamped<T>& operator[](std::size_t i) const { return samples_[i]; }
  const std::vector<Stamped<T>>& samples() const { return samples_; }
  double frontStamp() const { return samples_.front().stamp_s; }
  double backStamp() const { return samples_.back().stamp_s; }

  /// True when t lies inside [first stamp, last stamp].
  bool covers(double t) const { return !samples_.empty() && t >= frontStamp() && t <= backStamp(); }

  /// The two samples that bracket t; nullopt outside the series (no extrapolation).
  std::optional<Bracket> bracket(double t) const {
    if (!covers(t)) return std::nullopt;
    if (samples_.size() == 1) return Bracket{0, 0.0};
    auto upper = std::upper_bound(samples_.begin(), samples_.end(), t,
                                  [](double s, const Stamped<T>& x) { return s < x.stamp_s; });
    std::size_t i = std::min<std::size_t>(upper - samples_.begin(), samples_.size() - 1) - 1;
    const double dt = samples_[i + 1].stamp_s - samples_[i].stamp_s;
    return Bracket{i, (t - samples_[i].stamp_s) / dt};
  }

  /// Value at t, interpolated between the bracketing samples; nullopt outside the series.
  std::optional<T> at(double t) const {
    const auto b = bracket(t);
    if (!b) return std::nullopt;
    if (samples_.size() == 1) return samples_.front().value;
    return interpolateValue(samples_[b->index].value, samples_[b->index + 1].value, b->fraction);
  }

 private:
  std::vector<Stamped<T>> samples_;
};

using PoseSeries = TimeSeries<SE2>;

}  // namespace slamprep
