#pragma once
// Every constant-rate stream of a dataset put back on its grid where its stamps are measurably
// jittered (stamp_grid.hpp): encoders, the odometry poses, the IMU and the scans' first beams.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slamprep/algo/timing/stamp_grid.hpp"
#include "slamprep/core/dataset.hpp"

namespace slamprep::algo {

/// One stream's outcome (StampGrid without the stamps).
struct StreamStamps {
  std::string stream;  ///< "encoders", "odometry", "imu", "scans"
  std::size_t samples = 0;
  bool applied = false;
  std::string reason;
  double period_s = 0.0;
  double residual_rms_s = 0.0;
  double residual_max_s = 0.0;
  std::size_t missing_samples = 0;
  /// Kept because its own evidence says its stamps are right (the encoders' ticks, and the
  /// odometry stamped with them): residual_rms_s is then how irregularly it was sampled.
  bool stamped_right = false;
};

/// Regularises each stream of `dataset` in place; a stream that is regular already, not
/// constant-rate, too short, or stamped right by its own evidence (encoders whose ticks follow
/// their stamps, and the odometry stamped with them: StreamStamps::stamped_right) keeps its
/// stamps bit for bit, and when any stream has
/// no constant-rate grid every stream keeps its stamps (they were stamped by one host: moving
/// some would shift them against it). A scan's nominal odometry pose is re-read at its new stamp.
std::vector<StreamStamps> regularizeStamps(Dataset& dataset, const StampGridParams& params = {});

/// True when any stream's stamps were changed.
bool anyApplied(const std::vector<StreamStamps>& streams);

/// One line per regularised stream, e.g. "stamps: scans put on their 0.1 s grid (jitter RMS
/// 1.01 ms, max 2.99 ms)", and per stream kept as stamped right, e.g. "stamps: encoders kept as
/// stamped right: their ticks bound the stamp error to 0.63 ms, their 7.1 ms about the grid is
/// when they were sampled"; empty when neither.
std::string stampsSummary(const std::vector<StreamStamps>& streams);

}  // namespace slamprep::algo
