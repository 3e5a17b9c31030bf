#pragma once
// The dataset's odometry re-integrated with another wheel geometry: what `calibrate
// --odometry-out`, `export --calibration` and calibrate's held-out validation all write or score.
// One place, so that a log without encoder ticks (an imported CARMEN log) gets the same derived
// wheel increments everywhere (docs/calibration.md, "Logs without encoder ticks").

#include <optional>
#include <string>

#include "slamprep/core/dataset.hpp"

namespace slamprep::eval {

/// The encoders a dataset's odometry is re-integrated from, and where it starts.
struct OdometryEncoders {
  std::string source;  ///< the dataset, for messages
  EncoderLog encoders;
  int ticks_per_revolution = 0;
  SE2 T_odom_base0;  ///< the nominal odometry's pose at the first encoder stamp
  /// Set when the log had no encoder ticks: the geometry the increments were derived from its
  /// odometry poses with.
  std::optional<DiffDriveParams> derived_with;
};

/// The dataset's encoders or, when it has fewer than two encoder samples but odometry poses,
/// increments derived from the poses with `nominal` (default: dataset.json's geometry).
OdometryEncoders odometryEncoders(const Dataset& dataset, const std::string& source,
                                  const std::optional<DiffDriveParams>& nominal = std::nullopt);

/// T_odom_base at every encoder stamp, integrated with `geometry` from T_odom_base0. Throws
/// InputError naming the source when there is nothing to integrate (fewer than two samples):
/// an empty trajectory is never a result.
PoseSeries integrateOdometry(const OdometryEncoders& encoders, const DiffDriveParams& geometry);

/// odometryEncoders then integrateOdometry.
PoseSeries calibratedOdometry(const Dataset& dataset, const std::string& source,
                              const DiffDriveParams& geometry,
                              const std::optional<DiffDriveParams>& nominal = std::nullopt);

}  // namespace slamprep::eval
