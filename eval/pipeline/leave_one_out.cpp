#include "slamprep/eval/pipeline/leave_one_out.hpp"

#include <optional>
#include <string>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"

namespace slamprep::eval {
namespace {

/// A whole recording scored as a held-out part is (scorePart); `why` also when it cannot be read.
ScoredPart wholeRecording(const RecordingCalibration& rec, const HeldOutParams& params) {
  try {
    return scorePart(readDataset(rec.dataset), rec.calibration, params);
  } catch (const InputError& e) {
    return {{}, std::nullopt, e.what()};
  }
}

algo::LeaveOneOutScore score(const RecordingsCalibration& r, const RecordingsCalibrationParams& p,
                             algo::CalibrationMethod method, std::size_t i,
                             const ScoredPart& whole) {
  const RecordingCalibration& rec = r.recordings[i];
  algo::LeaveOneOutScore s{rec.dataset, 0, std::nullopt,
                           whole.raw ? "" : "not scored: " + whole.why};
  const algo::CombinedRun others =
      algo::combineRuns(method, methodRuns(r.recordings, method, i), p.combine);
  s.others = others.recordings.size();
  if (!others.run.result.ok) {
    s.note = "not scored: the other recordings give no estimate (" + others.run.result.reason + ")";
    return s;
  }
  if (!whole.raw) return s;
  s.figures =
      validationFigures(whole.part, *whole.raw, others.run, rec.calibration.T_base_lidar, 1.0);
  return s;
}

}  // namespace

std::vector<algo::LeaveOneOutMethod> leaveOneOut(const RecordingsCalibration& r,
                                                 const RecordingsCalibrationParams& params) {
  std::vector<ScoredPart> whole;
  for (const RecordingCalibration& rec : r.recordings)
    whole.push_back(wholeRecording(rec, params.held_out));
  std::vector<algo::LeaveOneOutMethod> out;
  for (const algo::CombinedRun& c : r.combined) {
    algo::LeaveOneOutMethod m{c.run.method, {}};
    for (std::size_t i = 0; i < r.recordings.size(); ++i)
      m.recordings.push_back(score(r, params, c.run.method, i, whole[i]));
    out.push_back(std::move(m));
  }
  return out;
}

}  // namespace slamprep::eval
