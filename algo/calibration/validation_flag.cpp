#include "algo/calibration/validation_flag.hpp"

#include <cstdio>

namespace slamprep::algo {
namespace {

bool worse(double calibrated, double raw, double floor, const ValidationFlagParams& p) {
  return calibrated > raw * (1.0 + p.max_relative_increase) + floor;
}

double ratio(double calibrated, double raw) {
  return raw > 0.0 ? calibrated / raw : 0.0;
}

}  // namespace

std::optional<NominalFlag> validationFlag(const ValidationFigures& v,
                                          const ValidationFlagParams& params) {
  const bool trans = worse(v.calibrated.trans_m, v.raw.trans_m, params.floor_trans_m, params);
  const bool rot = worse(v.calibrated.rot_deg, v.raw.rot_deg, params.floor_rot_deg, params);
  if (!trans && !rot) return std::nullopt;
  char cause[400];
  std::snprintf(cause, sizeof cause,
                "on the held-out %.0f %% the calibrated geometry predicts the motion worse than "
                "the nominal (translation %.3f vs %.3f m, rotation %.2f vs %.2f deg): the "
                "calibration part does not pin the geometry down (little turning or straight "
                "driving, slip, a clock lag) or the robot changed; keep the nominal or "
                "calibrate on a longer drive",
                v.fraction * 100.0, v.calibrated.trans_m, v.raw.trans_m, v.calibrated.rot_deg,
                v.raw.rot_deg);
  const double r = trans ? ratio(v.calibrated.trans_m, v.raw.trans_m)
                         : ratio(v.calibrated.rot_deg, v.raw.rot_deg);
  return NominalFlag{"held_out", r, cause};
}

}  // namespace slamprep::algo
