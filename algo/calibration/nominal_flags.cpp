#include "slamprep/algo/calibration/nominal_flags.hpp"

#include <array>
#include <cmath>

namespace slamprep::algo {
namespace {

constexpr const char* kTranslationCause =
    "the wheel increments do not match the scan-matched translation: wrong nominal radius, stale "
    "odometry (encoders not updated while the robot moves), or a scale error of the matcher "
    "(long featureless corridors)";
constexpr const char* kOneWheelCause =
    "the two wheels disagree: a wrong radius or ticks per revolution on one side, an encoder "
    "channel miscounting, or heading drift of the scan matching, which reads as r_R != r_L";
constexpr const char* kRotationCause =
    "rotation from the scans and the wheels disagree: wheel slip in turns, a gyro-heading "
    "odometry, a blocked robot, or a wrong nominal b";

// The cause of the pattern of ratios (r_L, r_R, b) / nominal, given which are off.
const char* likelyCause(const std::array<double, 3>& ratio, const std::array<bool, 3>& off,
                        int param) {
  const bool radii_together = off[0] && off[1] && (ratio[0] > 1.0) == (ratio[1] > 1.0);
  if (radii_together) return kTranslationCause;  // b, if off too, inherits the scale
  if (param < 2 || off[0] || off[1]) return kOneWheelCause;
  return kRotationCause;
}

}  // namespace

std::vector<NominalFlag> nominalFlags(const CalibrationResult& result,
                                      const DiffDriveParams& nominal,
                                      const NominalFlagParams& params) {
  std::vector<NominalFlag> flags;
  if (!result.ok) return flags;
  const DiffDriveParams& g = result.geometry;
  const std::array<double, 3> ratio = {g.radius_left_m / nominal.radius_left_m,
                                       g.radius_right_m / nominal.radius_right_m,
                                       g.wheel_base_m / nominal.wheel_base_m};
  std::array<bool, 3> off{};
  for (int i = 0; i < 3; ++i) off[i] = std::abs(ratio[i] - 1.0) > params.max_relative_deviation;
  for (int i = 0; i < 3; ++i)
    if (off[i]) flags.push_back({kCalibrationKeys[i], ratio[i], likelyCause(ratio, off, i)});
  return flags;
}

}  // namespace slamprep::algo
