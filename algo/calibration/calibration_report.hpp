#pragma once
// Everything `slamprep calibrate --json` writes (docs/calibration.md): the runs of one or several
// recordings, each method's flags and held-out validation, and for several recordings the
// combined estimate and its consistency. calibration_json.hpp turns it into the one JSON text;
// a new key (e.g. one more object per method or for the whole file) is added to this report and
// to formatCalibrateJson, nowhere else.

#include <optional>
#include <string>
#include <vector>

#include "slamprep/algo/agreement/sensor_agreement.hpp"
#include "slamprep/algo/calibration/against_nominal.hpp"
#include "slamprep/algo/calibration/calibrate.hpp"
#include "slamprep/algo/calibration/nominal_flags.hpp"
#include "slamprep/core/se2.hpp"

namespace slamprep::algo {

/// The true geometry and mount, for the JSON's "error" object.
struct CalibrationTruth {
  DiffDriveParams geometry;
  SE2 T_base_lidar;
  Eigen::VectorXd values() const;  ///< all six, in kCalibrationKeys order
};

/// An odometry's relative pose error on the held-out part of a recording.
struct HeldOutError {
  double trans_m = 0.0;  ///< mean translation error over the windows
  double rot_deg = 0.0;  ///< mean absolute rotation error
};

/// `calibrate --validate-fraction`: the nominal and the calibrated geometry on held-out data.
struct ValidationFigures {
  double fraction = 0.0;
  HeldOutError raw;
  HeldOutError calibrated;  ///< the calibrated wheels, and the calibrated mount where estimated
  /// The calibrated wheels with the dataset's mount, where the method estimates a mount: the
  /// odometry alone, apart from a mount the recording may not pin down.
  std::optional<HeldOutError> calibrated_wheels;
};

/// One method's run and what is said about it.
struct MethodReport {
  CalibrationRun run;
  std::vector<NominalFlag> flags;               ///< "flags" (written when not empty)
  std::optional<ValidationFigures> validation;  ///< "validation" (with --validate-fraction)
  std::optional<NominalTest> against_nominal;   ///< "against_nominal" (ok, with a nominal)
};

/// One recording (DATASET) and its methods.
struct RecordingReport {
  std::string dataset;
  std::vector<MethodReport> methods;
  std::optional<CalibrationTruth> truth;  ///< for "error"
  /// "sensor_agreement" (one recording: in every method object, the list staying a list).
  std::optional<SensorAgreement> agreement;
  std::string encoders_from;
  /// "clock_sync_s": what `--sync auto` added to the wheels' stamps (0: nothing; one recording:
  /// in every method object).
  double clock_sync_s = 0.0;
};

/// chi2/dof of one parameter of one method over the recordings (combine_recordings.hpp).
struct ParameterConsistency {
  std::string param;
  double chi2_dof = 0.0;  ///< NaN (written null) when n < 2
  int n = 0;              ///< recordings where the method was ok
};

struct MethodConsistency {
  CalibrationMethod method = CalibrationMethod::kDirect;
  std::vector<ParameterConsistency> params;
};

/// One recording scored whole with the combination of the OTHER recordings' estimates
/// (`calibrate DATASET... --leave-one-out`): does a calibration hold on the next run?
struct LeaveOneOutScore {
  std::string dataset;
  std::size_t others = 0;                    ///< the other recordings' ok estimates combined
  std::optional<ValidationFigures> figures;  ///< fraction 1: the whole recording; absent: note
  std::string note;                          ///< why the recording was not scored
};

struct LeaveOneOutMethod {
  CalibrationMethod method;
  std::vector<LeaveOneOutScore> recordings;  ///< in the order of the DATASETs
};

/// On how many scored recordings the calibrated odometry beat raw (JSON "beats_raw").
struct BeatsRaw {
  int trans = 0, rot = 0, scored = 0;
};

inline BeatsRaw beatsRaw(const LeaveOneOutMethod& m) {
  BeatsRaw b;
  for (const LeaveOneOutScore& s : m.recordings) {
    if (!s.figures) continue;
    ++b.scored;
    b.trans += s.figures->calibrated.trans_m < s.figures->raw.trans_m;
    b.rot += s.figures->calibrated.rot_deg < s.figures->raw.rot_deg;
  }
  return b;
}

struct CalibrateReport {
  /// One: the JSON is today's list of method objects. Several: the object with "recordings",
  /// "combined" and "consistency".
  std::vector<RecordingReport> recordings;
  std::vector<MethodReport> combined;
  std::optional<CalibrationTruth> combined_truth;  ///< when every recording has the same truth
  std::vector<MethodConsistency> consistency;
  std::vector<LeaveOneOutMethod> leave_one_out;  ///< with --leave-one-out
};

}  // namespace slamprep::algo
