#pragma once
// Held-out validation as a verdict (docs/calibration.md, "Flags"): a geometry that predicts the
// held-out part of a recording worse than the nominal one did is not an improvement, however
// small its sigma. Real recordings showed it: of 13 short Neato recordings that calibrated,
// 10 had calibrated odometry worse than the raw one on their held-out part, all with sigmas of
// a few millimetres, and nothing said so.

#include <optional>

#include "slamprep/algo/calibration/calibration_report.hpp"

namespace slamprep::algo {

struct ValidationFlagParams {
  /// Flagged when calibrated > raw x (1 + max_relative_increase) + floor, in translation or
  /// rotation: within 10 % the two are not told apart by a few held-out windows.
  double max_relative_increase = 0.10;
  double floor_trans_m = 0.002;  ///< below the scan matching's own error per window
  double floor_rot_deg = 0.05;
};

/// A flag with param "held_out" and ratio calibrated / raw (of translation, or of rotation when
/// only rotation got worse), or nullopt when the calibrated geometry is not worse. Its cause
/// names the mount when the calibrated wheels with the dataset's mount are not worse, and says
/// so when the calibration part did not show the nominal geometry wrong (`against_nominal`):
/// then the calibration moved the odometry by no more than its own uncertainty.
std::optional<NominalFlag> validationFlag(
    const ValidationFigures& validation, const ValidationFlagParams& params = {},
    const std::optional<NominalTest>& against_nominal = std::nullopt);

}  // namespace slamprep::algo
