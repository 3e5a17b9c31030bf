#pragma once
// A sensor's heading over time: the yaw it says the robot turned, cumulative and unwrapped, so
// that what it turned between two times is a difference (docs/design.md "Sensor agreement").

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

/// What `heading` turned from t0 to t1; nullopt where it does not cover both or, inside them,
/// two samples lie more than max_gap_s apart (nothing is known of the turn in between).
std::optional<double> turned(const HeadingSeries& heading, double t0_s, double t1_s,
                             double max_gap_s);

}  // namespace slamprep
