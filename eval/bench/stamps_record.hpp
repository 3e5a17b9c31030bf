#pragma once
// Jittered stamps put back on their grids in a trial ("stamps" of a trial result, written only
// when a stream was moved): per stream what algo::regularizeStamps did (docs/deskew.md,
// "Jittered stamps").

#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slamprep/algo/timing/dataset_stamps.hpp"

namespace slamprep::eval {

/// One stream's outcome (algo::StreamStamps without its name, which keys it).
struct StreamStampsRecord {
  bool applied = false;             ///< its stamps were moved onto the grid
  std::string reason;               ///< why not, when not
  std::size_t samples = 0;          ///< stamps in the stream
  double period_s = 0.0;            ///< the grid's period
  double residual_rms_s = 0.0;      ///< RMS distance of the stamps to the grid
  double residual_max_s = 0.0;      ///< largest distance
  std::size_t missing_samples = 0;  ///< grid slots without a sample

  bool operator==(const StreamStampsRecord&) const = default;
};

/// Stream name ("encoders", "odometry", "imu", "scans") -> its outcome.
using StampsRecord = std::map<std::string, StreamStampsRecord>;

StampsRecord stampsRecord(const std::vector<algo::StreamStamps>& streams);

void to_json(nlohmann::json& out, const StreamStampsRecord& r);
void from_json(const nlohmann::json& in, StreamStampsRecord& r);

}  // namespace slamprep::eval
