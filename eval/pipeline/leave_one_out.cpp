#include "slamprep/eval/pipeline/leave_one_out.hpp"

#include <algorithm>
#include <optional>
#include <string>

#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"

namespace slamprep::eval {
namespace {

/// A whole recording as a held-out part, with the raw geometry's error on it.
struct WholeRecording {
  std::optional<HeldOutPart> part;
  algo::HeldOutError raw;
  std::string note;  ///< why there is no part
};

WholeRecording wholeRecording(const RecordingCalibration& rec, const HeldOutParams& params) {
  WholeRecording out;
  // The wheels on the scans' clock, as the calibration had them (--sync).
  OdometryEncoders odometry = rec.calibration.odometry;
  for (EncoderSample& e : odometry.encoders) e.stamp_s += rec.calibration.clock_offset_s;
  try {
    out.part = heldOutPart(readDataset(rec.dataset), odometry, params);
    out.raw = heldOutError(*out.part, rec.calibration.nominal, rec.calibration.T_base_lidar);
  } catch (const InputError& e) {
    out.part.reset();
    out.note = std::string("not scored: ") + e.what();
  }
  return out;
}

/// Recording `skip`'s others' runs of `method` (nullptr where it did not run or is skipped).
std::vector<const algo::CalibrationRun*> othersRuns(const RecordingsCalibration& r,
                                                    algo::CalibrationMethod method,
                                                    std::size_t skip) {
  std::vector<const algo::CalibrationRun*> runs;
  for (std::size_t i = 0; i < r.recordings.size(); ++i) {
    const auto& all = r.recordings[i].calibration.runs;
    const auto it = std::find_if(all.begin(), all.end(),
                                 [&](const algo::CalibrationRun& x) { return x.method == method; });
    runs.push_back(i == skip || it == all.end() ? nullptr : &*it);
  }
  return runs;
}

algo::LeaveOneOutScore score(const RecordingsCalibration& r, const RecordingsCalibrationParams& p,
                             algo::CalibrationMethod method, std::size_t i,
                             const WholeRecording& whole) {
  const RecordingCalibration& rec = r.recordings[i];
  algo::LeaveOneOutScore s{rec.dataset, 0, std::nullopt, whole.note};
  const algo::CombinedRun others = algo::combineRuns(method, othersRuns(r, method, i), p.combine);
  s.others = others.recordings.size();
  if (!others.run.result.ok) {
    s.note = "not scored: the other recordings give no estimate (" + others.run.result.reason + ")";
    return s;
  }
  if (!whole.part) return s;
  s.figures =
      validationFigures(*whole.part, whole.raw, others.run, rec.calibration.T_base_lidar, 1.0);
  return s;
}

}  // namespace

std::vector<algo::LeaveOneOutMethod> leaveOneOut(const RecordingsCalibration& r,
                                                 const RecordingsCalibrationParams& params) {
  std::vector<WholeRecording> whole;
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
