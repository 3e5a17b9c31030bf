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

}  // namespace slamprep::algo
