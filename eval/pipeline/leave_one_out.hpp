#pragma once
// `slamprep calibrate DATASET DATASET ... --leave-one-out` (docs/calibration.md, "Leave one
// recording out"): every recording scored whole, against its scan-to-map matched trajectory,
// with the combination of the OTHER recordings' estimates and with the raw geometry. A held-out
// tail of one short recording (--validate-fraction) is seconds long; a whole recording of the
// same robot is what a calibration is for: the next run.

#include <vector>

#include "slamprep/algo/calibration/calibration_report.hpp"
#include "slamprep/eval/pipeline/recordings_calibration.hpp"

namespace slamprep::eval {

/// Per method of `r.combined`, per recording i: the other recordings' runs of that method
/// combined (algo::combineRuns) and scored on recording i's whole trajectory. A recording whose
/// scans cannot be tracked, or whose others have no ok estimate, is not scored (its note says
/// why). Reads and matches every recording again.
std::vector<algo::LeaveOneOutMethod> leaveOneOut(const RecordingsCalibration& r,
                                                 const RecordingsCalibrationParams& params);

}  // namespace slamprep::eval
