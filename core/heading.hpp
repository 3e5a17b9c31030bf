#pragma once
// A sensor's heading over time: the yaw it says the robot turned, cumulative and unwrapped, so
// that what it turned between two times is a difference (docs/design.md "Sensor agreement").

#include <cmath>
#include <cstddef>
#include <optional>

#include "slamprep/core/samples.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep {

/// Cumulative yaw (rad, unwrapped: 3 turns read 6 pi) at each sample's stamp.
using HeadingSeries = TimeSeries<double>;

/// The gyro's yaw rate integrated (trapezoid between samples), 0 at the first sample.
HeadingSeries gyroHeading(const ImuLog& imu);

/// The poses' yaw, unwrapped (each step taken as the shorter way round).
HeadingSeries poseHeading(const PoseSeries& poses);

/// The poses' signed travel along their heading, cumulative (m): each step's displacement
/// projected onto the mean of its two headings, so reversing counts negative.
TimeSeries<double> poseTravel(const PoseSeries& poses);

/// What a cumulative series (a heading, wheel angles, a travel) turned from t0 to t1; nullopt
/// where it does not cover both or, inside them, two samples lie more than max_gap_s apart
/// (nothing is known of the turn in between; an infinite max_gap_s checks nothing).
template <typename T>
std::optional<T> turned(const TimeSeries<T>& series, double t0_s, double t1_s, double max_gap_s) {
  const auto b0 = series.bracket(t0_s), b1 = series.bracket(t1_s);
  if (!b0 || !b1) return std::nullopt;
  if (std::isfinite(max_gap_s))
    for (std::size_t k = b0->index; k + 1 < series.size() && series[k].stamp_s < t1_s; ++k)
      if (series[k + 1].stamp_s - series[k].stamp_s > max_gap_s) return std::nullopt;
  return T(*series.at(t1_s) - *series.at(t0_s));
}

}  // namespace slamprep
