#pragma once
// `slamprep calibrate DATASET [DATASET ...]` (docs/calibration.md, "Several recordings"): each
// recording calibrated on its own (optionally on its first part, scored on the held-out rest),
// its estimates flagged when far from the nominal geometry, then one combined estimate per
// method with the recordings' consistency; and the report `--json` writes.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/algo/calibration/calibration_report.hpp"
#include "slamprep/algo/calibration/combine_recordings.hpp"
#include "slamprep/algo/calibration/nominal_flags.hpp"
#include "slamprep/eval/pipeline/calibration_run.hpp"
#include "slamprep/eval/pipeline/calibration_validation.hpp"

namespace slamprep::eval {

struct RecordingsCalibrationParams {
  /// What each recording runs; its `dataset` is replaced by each of `datasets` in turn.
  DatasetCalibrationParams base;
  /// The recordings; empty: base as it is (one recording, e.g. --tuples alone).
  std::vector<std::string> datasets;
  double validate_fraction = 0.0;  ///< 0: no held-out validation, else in (0, 1)
  /// With several recordings: each one scored whole with the others' combination (leaveOneOut).
  bool leave_one_out = false;
  HeldOutParams held_out;
  algo::CombineParams combine;
  algo::NominalFlagParams flags;
};

struct RecordingCalibration {
  std::string dataset;
  DatasetCalibration calibration;       ///< of the calibration part with validation
  std::optional<HeldOutPart> held_out;  ///< with validation, where the part could be scored
  algo::HeldOutError held_out_raw;      ///< the nominal geometry's error on held_out
  std::string validation_note;          ///< why a held-out part was not scored
};

/// Each recording's run of `method`: nullptr where it did not run, and for recording `skip`
/// (leave one out; the default skips none).
std::vector<const algo::CalibrationRun*> methodRuns(const std::vector<RecordingCalibration>& recs,
                                                    algo::CalibrationMethod method,
                                                    std::size_t skip = SIZE_MAX);

/// A part of a recording scored as every geometry is: its scans tracked (heldOutPart), the
/// calibration's wheels moved onto the scans' clock as the intervals had them (--sync), and the
/// nominal geometry's error on it.
struct ScoredPart {
  HeldOutPart part;
  std::optional<algo::HeldOutError> raw;  ///< absent: the part could not be scored (`why`)
  std::string why;
};

ScoredPart scorePart(const Dataset& scans, const DatasetCalibration& calibration,
                     const HeldOutParams& params);

struct RecordingsCalibration {
  std::vector<RecordingCalibration> recordings;
  /// With several recordings: one per method, in the order the first recording ran them.
  std::vector<algo::CombinedRun> combined;
  algo::CalibrateReport report;  ///< what --json writes
};

/// Throws InputError naming the datasets when their nominal geometries differ (unless
/// `nominal` is given, which then applies to all): one robot has one nominal geometry. Reads
/// only dataset.json.
void checkSameNominal(const std::vector<std::string>& datasets,
                      const std::optional<DiffDriveParams>& nominal);

/// Runs everything; `done(dataset)` after each recording.
RecordingsCalibration calibrateRecordings(const RecordingsCalibrationParams& params,
                                          const std::function<void(const std::string&)>& done = {});

/// Recording i's figures for the combined geometry where it has a held-out part: the mean over
/// the recordings of each one's held-out error (raw and calibrated).
std::optional<algo::ValidationFigures> combinedValidation(const RecordingsCalibration& r,
                                                          const algo::CalibrationRun& combined,
                                                          double fraction);

}  // namespace slamprep::eval
