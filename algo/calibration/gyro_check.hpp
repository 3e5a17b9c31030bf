#pragma once
// The gyro as an independent check of a calibrated wheel base (docs/calibration.md, "Sensor
// agreement"): the wheels-against-gyro fit of the sensor agreement (algo/agreement, Eq. 1) is
// the lecture's IMU calibration of a = r_R / b and c = r_L / b, with no scan matching in it.
// With a result's own radii it implies b_gyro = (r_L + r_R) / (a + c). A result whose b differs
// from that by more than its own uncertainty allows has its rotation from somewhere the gyro
// does not agree with: a drifting scan-matched heading, a gyro scale error, or slip in turns.

#include <optional>

#include "slamprep/algo/agreement/sensor_agreement.hpp"
#include "slamprep/algo/calibration/calibration_result.hpp"
#include "slamprep/algo/calibration/nominal_flags.hpp"

namespace slamprep::algo {

struct GyroCheckParams {
  /// Flagged when |b / b_gyro - 1| exceeds max(sigmas x sigma_b / b, min_relative).
  double sigmas = 3.0;
  double min_relative = 0.03;
};

/// b_gyro for an ok result, where the agreement has the wheels-against-gyro fit.
std::optional<double> gyroWheelBase(const CalibrationResult& result,
                                    const SensorAgreement& agreement);

/// A flag with param "b_vs_gyro" and ratio b / b_gyro, or nullopt where they agree.
std::optional<NominalFlag> gyroFlag(const CalibrationResult& result,
                                    const SensorAgreement& agreement,
                                    const GyroCheckParams& params = {});

/// Without a gyro, the wheels against the scans: a flag with param "wheels_vs_scans" (ratio 1)
/// where they disagree beyond any wheel geometry (a lifted or blocked robot, or failed scan
/// matches: nothing tells which), naming the spans. With a gyro, calibrate refuses on the
/// wheels against the gyro instead.
std::optional<NominalFlag> wheelsScansFlag(const CalibrationResult& result,
                                           const SensorAgreement& agreement);

/// A flag with param "b_not_measured" (ratio 1) where the wheels follow the gyro
/// (SensorAgreement::wheels_follow_gyro): the b of such a result is the gyro's rotation against
/// the scans', whatever the wheels are.
std::optional<NominalFlag> gyroHeadedWheelsFlag(const CalibrationResult& result,
                                                const SensorAgreement& agreement);

}  // namespace slamprep::algo
