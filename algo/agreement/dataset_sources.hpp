#pragma once
// The rotation sources of a dataset for compareSensors(): its wheel encoders, its gyro, the
// robot's own odometry topic where the encoders were not derived from it, and a scan-matched
// trajectory when one was computed.

#include <functional>
#include <string>
#include <vector>

#include "slamprep/algo/agreement/sensor_agreement.hpp"
#include "slamprep/core/dataset.hpp"

namespace slamprep::algo {

/// Where a dataset's encoders came from: "ticks" (simulated or logged ticks), "joint_states"
/// (JointState wheel angles) or "odometry_poses" (derived from the odometry topic's poses, so
/// they are that topic, not independent wheels). dataset.json config "encoders_from", else read
/// from the importer's "encoders" text.
std::string encodersFrom(const DatasetInfo& info);

/// Wheels, gyro and odometry topic of `dataset`; `scan_pieces` the scan-matched heading (see
/// RotationSources::scans), empty when nothing was matched.
RotationSources datasetSources(const Dataset& dataset, std::vector<HeadingSeries> scan_pieces = {});

/// Scan headings from matched poses: one piece per pose series.
std::vector<HeadingSeries> scanPieces(const std::vector<PoseSeries>& matched);

/// The wheels against the scans, or where there are no encoders the odometry poses against them.
const PairAgreement* wheelsAgainstScans(const SensorAgreement& agreement);

/// How far the wheels' and the gyro's stamps are moved onto the scans' clock: the delays of the
/// scans behind them that the agreement measured, each where over min_lag_s; nothing at all
/// (both 0) where the wheels' is not. A dataset without encoders has its odometry poses for
/// wheels (a CARMEN log's, a bag with /odom only).
struct ClockShift {
  double wheels_s = 0.0, gyro_s = 0.0;
  bool any() const { return wheels_s != 0.0; }
};
ClockShift scanClockShift(const SensorAgreement& agreement, double min_lag_s);

/// The wheels (encoder samples and the odometry poses) and the gyro moved by `shift`.
void shiftOntoScanClock(Dataset& dataset, const ClockShift& shift);

/// Matches the dataset's scans and returns the scan-matched poses (one series per chain).
using MatchScans = std::function<std::vector<PoseSeries>(const Dataset&)>;

/// The clock sync of calibrate and match. Where `first` finds the scans lagging the wheels by
/// over min_lag_s: the wheels and gyro moved onto the scans' clock and the scans matched again
/// (their de-skew and guesses read the wheels and gyro at each beam's time); then what delay is
/// left, measured on that match where a delay shows most (1 s windows every 0.25 s, within
/// +-0.1 s), moved where over min_left_s and matched once more: the first measure was made on
/// scans de-skewed with the motion of another moment (0.27 s read as 0.2 s). Where what is left
/// takes the first back (the two within min_lag_s of each other), the first was no delay: the
/// streams are put back as logged and matched again (a long log's first measure of 44 ms came
/// back as 6 ms in all, and the match after it had moved the calibration by 10 %). Returns the
/// total moved (0: nothing; matched again only where something was moved on the way).
double syncOntoScanClock(Dataset& dataset, const SensorAgreement& first, double min_lag_s,
                         double min_left_s, const MatchScans& match_again);

}  // namespace slamprep::algo
