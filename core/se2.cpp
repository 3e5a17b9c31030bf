#include "slamprep/core/se2.hpp"

#include <cmath>
#include <numbers>

namespace slamprep {

double normalizeAngle(double angle_rad) {
  constexpr double kPi = std::numbers::pi;
  // Inside (-pi, pi] std::remainder returns its argument exactly (the quotient rounds to 0):
  // skipping the call there changes no bit and saves most of its cost on the hot paths.
  if (angle_rad > -kPi && angle_rad <= kPi) return angle_rad;
  const double a = std::remainder(angle_rad, 2.0 * kPi);  // in [-pi, pi]
  return a <= -kPi ? a + 2.0 * kPi : a;
}

template struct SE2T<double>;

}  // namespace slamprep
