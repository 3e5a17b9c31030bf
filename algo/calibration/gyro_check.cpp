#include "slamprep/algo/calibration/gyro_check.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "slamprep/algo/agreement/agreement_report.hpp"

namespace slamprep::algo {

std::optional<double> gyroWheelBase(const CalibrationResult& result,
                                    const SensorAgreement& agreement) {
  const PairAgreement* p = agreement.pair("wheels", "gyro");
  if (!result.ok || !p || !p->wheel_ratios) return std::nullopt;
  const double sum = (*p->wheel_ratios)(0) + (*p->wheel_ratios)(1);  // (r_R + r_L) / b
  if (!(sum > 0.0)) return std::nullopt;
  return (result.geometry.radius_left_m + result.geometry.radius_right_m) / sum;
}

std::optional<NominalFlag> gyroFlag(const CalibrationResult& result,
                                    const SensorAgreement& agreement,
                                    const GyroCheckParams& params) {
  const auto b_gyro = gyroWheelBase(result, agreement);
  if (!b_gyro) return std::nullopt;
  const double b = result.geometry.wheel_base_m;
  const double sigma_b = result.covariance.size() > 0 ? std::sqrt(result.covariance(2, 2)) : 0.0;
  const double limit = std::max(params.sigmas * sigma_b / b, params.min_relative);
  if (std::abs(b / *b_gyro - 1.0) <= limit) return std::nullopt;
  char cause[320];
  std::snprintf(cause, sizeof cause,
                "the gyro implies b = %.1f mm with these radii: the rotation the calibration "
                "took from the scans disagrees with the gyro's (a drifting scan-matched "
                "heading, a gyro scale error, or slip in turns)",
                *b_gyro * 1e3);
  return NominalFlag{"b_vs_gyro", b / *b_gyro, cause};
}

std::optional<NominalFlag> wheelsScansFlag(const CalibrationResult& result,
                                           const SensorAgreement& agreement) {
  const PairAgreement* p = agreement.wheelsScansConflict();
  if (!result.ok || !p) return std::nullopt;
  return NominalFlag{"wheels_vs_scans", 1.0,
                     "the wheels and the scans disagree beyond what any wheel geometry explains, "
                     "and no gyro tells which is wrong (a lifted or blocked robot, or failed scan "
                     "matches); the intervals there entered the fit unless trimmed as outliers "
                     "(--exclude-disagreement leaves them out):" +
                         spansText(agreement, *p)};
}

std::optional<NominalFlag> gyroHeadedWheelsFlag(const CalibrationResult& result,
                                                const SensorAgreement& agreement) {
  if (!result.ok || !agreement.wheels_follow_gyro) return std::nullopt;
  return NominalFlag{"b_not_measured", 1.0,
                     "the wheel increments were derived from an odometry topic that turns as the "
                     "gyro does (to within 1 %): if its heading is the gyro's (e.g. TurtleBot3's "
                     "use_imu), b compares the gyro with the scans, not the wheels; record the "
                     "wheel joints (/joint_states) to calibrate b"};
}

}  // namespace slamprep::algo
