#pragma once
// What `slamprep calibrate` prints (docs/calibration.md): the per-method table of one
// recording, the compact tables of several and their combination with chi2/dof, the flags and
// the held-out validation.

#include <optional>
#include <vector>

#include "slamprep/algo/calibration/calibration_report.hpp"
#include "slamprep/eval/pipeline/recordings_calibration.hpp"

namespace slamprep::app {

/// One recording in full: every method's intervals, trimming and estimates (with truth, the
/// error columns).
void printTable(const std::vector<algo::CalibrationRun>& rows,
                const std::optional<algo::CalibrationTruth>& truth);

/// Several recordings: one compact block per recording, then the combined table with chi2/dof
/// per parameter and a warning for every method whose recordings disagree beyond their sigmas.
void printRecordings(const eval::RecordingsCalibration& r);

/// The flags of `methods` ("label" names the recording or "combined").
void printFlags(const std::vector<algo::MethodReport>& methods, const std::string& label);

/// Each method's estimate against the nominal geometry: per parameter in sigmas, the chi2 of the
/// three together and, after `data` ("the recording shows", "the recordings show"), whether
/// the nominal is shown wrong.
void printAgainstNominal(const std::vector<algo::MethodReport>& methods, const std::string& label,
                         const std::string& data);

/// The held-out validation table, and which methods' calibrated odometry is worse than raw.
void printValidation(const std::vector<algo::MethodReport>& methods, const std::string& label);

/// --leave-one-out: per method, every recording scored with the others' combined estimate, and
/// on how many the calibrated odometry beat raw (nothing when `methods` is empty).
void printLeaveOneOut(const std::vector<algo::LeaveOneOutMethod>& methods);

}  // namespace slamprep::app
