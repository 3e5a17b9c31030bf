#pragma once
// The odometry and gyro of a twin (docs/twin.md "Odometry"): the encoder stream's rate and
// resolution, its gaps (where the import dropped stale odometry, or samples were lost), and the
// gyro's bias and noise where the robot stood still.

#include <cstddef>
#include <optional>
#include <string>

#include "slamprep/core/dataset.hpp"
#include "slamprep/eval/pipeline/calibration_run.hpp"

namespace slamprep::eval {

struct OdometryFit {
  double duration_s = 0.0;
  double encoder_rate_hz = 0.0;  ///< 1 / the stamps' period (algo::streamPeriod)
  int ticks_per_revolution = 0;  ///< dataset.json's (derived encoders: the derivation's)
  /// Steps longer than gap_periods median steps: stale runs the import dropped, lost samples.
  std::size_t gaps = 0;
  double gap_mean_s = 0.0;  ///< missing time per gap (the step minus one period)
  double gap_max_s = 0.0;
  bool has_imu = false;
  double imu_rate_hz = 0.0;
  std::size_t still_samples = 0;  ///< gyro samples where the wheels did not turn
  double gyro_bias_radps = 0.0;   ///< their mean ...
  double gyro_noise_radps = 0.0;  ///< ... and standard deviation
  /// Stamp jitter (s) where calibrate puts a stream back on its grid (algo::regularizeStamps):
  /// the RMS of its stamps about the grid; 0 where the stream is regular or is left alone.
  double encoders_jitter_s = 0.0;  ///< the encoders' (or the odometry poses' without ticks) ...
  double encoders_grid_jitter_s = 0.0;  ///< ... the RMS about the grid, ...
  /// ... no more than the ticks say the stamps can be wrong (nullopt: too few steady steps);
  /// an odometry sampled irregularly but stamped right jitters about its grid without error.
  std::optional<double> encoders_stamp_error_bound_s;
  /// The rest of the grid jitter: sampled at irregular times, stamped right.
  double encoders_sampling_jitter_s = 0.0;
  double imu_jitter_s = 0.0;
  double scans_jitter_s = 0.0;
  /// The wheels' rate the recording reaches: 99th percentile of |rate| over the encoder steps
  /// (the odometry's poses with the nominal geometry where there are no ticks); 0: unknown.
  double wheel_rate_p99_radps = 0.0;
};

struct OdometryFitParams {
  double gap_periods = 2.5;    ///< a step this many median steps long is a gap
  std::size_t min_still = 50;  ///< fewer still gyro samples: bias and noise are not fitted
};

OdometryFit fitOdometry(const Dataset& dataset, const OdometryFitParams& params = {});

/// How `twin` calibrates, the recording for its true geometry and both sides for --compare's
/// b and sigma_b: one method, the same flags on both, so the two figures compare.
inline constexpr const char* kTwinCalibrationFlags =
    "calibrate --method joint --motion map --keyframe-cm 20";

/// The joint calibration of kTwinCalibrationFlags on `dataset` (read from the folder `dir`).
DatasetCalibration calibrateForTwin(const std::string& dir, const Dataset& dataset);

}  // namespace slamprep::eval
