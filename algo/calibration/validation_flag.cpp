#include "slamprep/algo/calibration/validation_flag.hpp"

#include <cstdio>
#include <string>

namespace slamprep::algo {
namespace {

bool worse(double calibrated, double raw, double floor, const ValidationFlagParams& p) {
  return calibrated > raw * (1.0 + p.max_relative_increase) + floor;
}

double ratio(double calibrated, double raw) {
  return raw > 0.0 ? calibrated / raw : 0.0;
}

// "on the held-out F % the calibrated WHAT predicts the motion worse than the nominal (...)".
std::string worseThanNominal(const ValidationFigures& v, const char* what) {
  char text[240];
  std::snprintf(text, sizeof text,
                "on the held-out %.0f %% the calibrated %s predicts the motion worse than the "
                "nominal (translation %.3f vs %.3f m, rotation %.2f vs %.2f deg)",
                v.fraction * 100.0, what, v.calibrated.trans_m, v.raw.trans_m, v.calibrated.rot_deg,
                v.raw.rot_deg);
  return text;
}

std::string geometryCause(const ValidationFigures& v, const std::optional<NominalTest>& nominal) {
  if (nominal && !nominal->shows_nominal_wrong) {
    char text[240];
    std::snprintf(text, sizeof text,
                  ": the calibration part did not show the nominal geometry wrong (chi2 %.1f over "
                  "3, p %.2f), so the calibration moved the odometry within its own uncertainty; "
                  "keep the nominal",
                  nominal->chi2, nominal->p);
    return worseThanNominal(v, "geometry") + text;
  }
  return worseThanNominal(v, "geometry") +
         ": the calibration part does not pin the geometry down (little turning or straight "
         "driving, slip, a clock lag) or the robot changed; keep the nominal or calibrate on a "
         "longer drive";
}

// Worse only through the mount: a lidar offset is seen in turns, and little turning leaves it
// loose.
std::string mountCause(const ValidationFigures& v) {
  char wheels[160];
  std::snprintf(wheels, sizeof wheels,
                ", the calibrated wheels with the dataset's mount do not (%.3f m, %.2f deg)",
                v.calibrated_wheels->trans_m, v.calibrated_wheels->rot_deg);
  return worseThanNominal(v, "lidar mount") + wheels +
         ": the recording does not pin the mount down (too little turning); keep the dataset's "
         "mount";
}

}  // namespace

std::optional<NominalFlag> validationFlag(const ValidationFigures& v,
                                          const ValidationFlagParams& params,
                                          const std::optional<NominalTest>& against_nominal) {
  const bool trans = worse(v.calibrated.trans_m, v.raw.trans_m, params.floor_trans_m, params);
  const bool rot = worse(v.calibrated.rot_deg, v.raw.rot_deg, params.floor_rot_deg, params);
  if (!trans && !rot) return std::nullopt;
  const auto& w = v.calibrated_wheels;
  const bool wheels_fine = w && !worse(w->trans_m, v.raw.trans_m, params.floor_trans_m, params) &&
                           !worse(w->rot_deg, v.raw.rot_deg, params.floor_rot_deg, params);
  const double r = trans ? ratio(v.calibrated.trans_m, v.raw.trans_m)
                         : ratio(v.calibrated.rot_deg, v.raw.rot_deg);
  return NominalFlag{"held_out", r,
                     wheels_fine ? mountCause(v) : geometryCause(v, against_nominal)};
}

}  // namespace slamprep::algo
