#pragma once
// Estimates far from the nominal geometry, flagged with their likely cause
// (docs/calibration.md, "Flags"). A wheel is rarely 15 % off its datasheet: such an estimate
// more often says that the data break an assumption of the calibration.

#include <string>
#include <vector>

#include "slamprep/algo/calibration/calibration_result.hpp"
#include "slamprep/core/diff_drive.hpp"

namespace slamprep::algo {

struct NominalFlagParams {
  /// |estimate / nominal - 1| beyond this flags the parameter.
  double max_relative_deviation = 0.15;
};

/// One flagged parameter: "r_L", "r_R" or "b", estimate / nominal, and the likely cause.
struct NominalFlag {
  std::string param;
  double ratio = 1.0;
  std::string likely_cause;
};

/// The flags of an ok result (none for a refused one), in r_L, r_R, b order. The cause is read
/// from the pattern of the three ratios: both radii off in the same direction (a translation
/// scale), one radius off or the two in opposite directions (one wheel), the wheel base off with
/// the radii near nominal (rotation).
std::vector<NominalFlag> nominalFlags(const CalibrationResult& result,
                                      const DiffDriveParams& nominal,
                                      const NominalFlagParams& params = {});

}  // namespace slamprep::algo
