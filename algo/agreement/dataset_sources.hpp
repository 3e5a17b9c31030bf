#pragma once
// The rotation sources of a dataset for compareSensors(): its wheel encoders, its gyro, the
// robot's own odometry topic where the encoders were not derived from it, and a scan-matched
// trajectory when one was computed.

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

/// How far the wheels' and the gyro's stamps are moved onto the scans' clock: the delays of the
/// scans behind them that the agreement measured, each where over min_lag_s; nothing at all
/// (both 0) where the wheels' is not.
struct ClockShift {
  double wheels_s = 0.0, gyro_s = 0.0;
  bool any() const { return wheels_s != 0.0; }
};
ClockShift scanClockShift(const SensorAgreement& agreement, double min_lag_s);

/// The agreement that measures what delay is left once synced: 1 s windows every 0.25 s (a
/// delay shows at a window's ends, where the turning rate changes), within +-0.1 s, any gain.
AgreementParams leftoverLagParams();

/// The wheels (encoder samples and the odometry poses) and the gyro moved by `shift`.
void shiftOntoScanClock(Dataset& dataset, const ClockShift& shift);

}  // namespace slamprep::algo
