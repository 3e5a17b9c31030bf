#include "slamprep/eval/pipeline/recordings_calibration.hpp"

#include <algorithm>
#include <filesystem>
#include <limits>
#include <nlohmann/json.hpp>

#include "slamprep/algo/calibration/calibration_json.hpp"
#include "slamprep/algo/calibration/gyro_check.hpp"
#include "slamprep/algo/calibration/mount_flag.hpp"
#include "slamprep/algo/calibration/scale_flag.hpp"
#include "slamprep/algo/calibration/validation_flag.hpp"
#include "slamprep/core/atomic_file.hpp"
#include "slamprep/core/error.hpp"
#include "slamprep/eval/formats/dataset_io.hpp"
#include "slamprep/eval/formats/dataset_json.hpp"
#include "slamprep/eval/pipeline/leave_one_out.hpp"

namespace slamprep::eval {
namespace {

std::string geometryText(const DiffDriveParams& g) {
  using nlohmann::json;
  return "r_L " + json(g.radius_left_m).dump() + ", r_R " + json(g.radius_right_m).dump() + ", b " +
         json(g.wheel_base_m).dump() + " m";
}

bool sameGeometry(const DiffDriveParams& a, const DiffDriveParams& b) {
  return a.radius_left_m == b.radius_left_m && a.radius_right_m == b.radius_right_m &&
         a.wheel_base_m == b.wheel_base_m;
}

algo::ValidationFigures validationOf(const RecordingCalibration& r, const algo::CalibrationRun& run,
                                     double fraction) {
  return validationFigures(*r.held_out, r.held_out_raw, run, r.calibration.T_base_lidar, fraction);
}

void accumulate(algo::HeldOutError& sum, const algo::HeldOutError& e) {
  sum.trans_m += e.trans_m;
  sum.rot_deg += e.rot_deg;
}

void divide(algo::HeldOutError& e, int n) {
  e.trans_m /= n;
  e.rot_deg /= n;
}

}  // namespace

std::vector<const algo::CalibrationRun*> methodRuns(const std::vector<RecordingCalibration>& recs,
                                                    algo::CalibrationMethod method,
                                                    std::size_t skip) {
  std::vector<const algo::CalibrationRun*> runs;
  for (std::size_t i = 0; i < recs.size(); ++i) {
    const auto& all = recs[i].calibration.runs;
    const auto it = std::find_if(all.begin(), all.end(),
                                 [&](const algo::CalibrationRun& x) { return x.method == method; });
    runs.push_back(i == skip || it == all.end() ? nullptr : &*it);
  }
  return runs;
}

ScoredPart scorePart(const Dataset& scans, const DatasetCalibration& calibration,
                     const HeldOutParams& params) {
  OdometryEncoders odometry = calibration.odometry;
  for (EncoderSample& e : odometry.encoders) e.stamp_s += calibration.clock_offset_s;
  ScoredPart out{heldOutPart(scans, odometry, params), std::nullopt, ""};
  try {
    out.raw = heldOutError(out.part, calibration.nominal, calibration.T_base_lidar);
  } catch (const InputError& e) {
    out.why = e.what();
  }
  return out;
}

namespace {

RecordingCalibration calibrateRecording(const RecordingsCalibrationParams& p,
                                        const std::string& dataset) {
  DatasetCalibrationParams params = p.base;
  if (!dataset.empty()) params.dataset = dataset;
  RecordingCalibration out{params.dataset, {}, std::nullopt, {}, ""};
  if (!(p.validate_fraction > 0.0)) {
    out.calibration = calibrateDataset(params);
    return out;
  }
  ValidationSplit split =
      splitForValidation(readDataset(params.dataset), p.validate_fraction, params.dataset);
  out.calibration = calibrateDataset(params, std::move(split.calibration));
  // A held-out part the matcher could not track is not scored; the calibration stands.
  ScoredPart scored = scorePart(split.held_out, out.calibration, p.held_out);
  if (scored.raw) {
    out.held_out = std::move(scored.part);
    out.held_out_raw = *scored.raw;
  } else {
    out.validation_note = "not validated: " + scored.why;
  }
  return out;
}

// What is said of m's estimate against the nominal geometry: its flags and its test.
void judgeAgainstNominal(algo::MethodReport& m, const DiffDriveParams& nominal,
                         const algo::NominalFlagParams& params) {
  m.flags = algo::nominalFlags(m.run.result, nominal, params);
  if (const auto flag = algo::scaleFlag(m.run.result, nominal)) m.flags.push_back(*flag);
  m.against_nominal = algo::nominalTest(m.run.result, nominal);
}

// The held-out verdict, once m's validation and nominal test are in.
void flagValidation(algo::MethodReport& m) {
  if (!m.validation) return;
  if (const auto flag = algo::validationFlag(*m.validation, {}, m.against_nominal))
    m.flags.push_back(*flag);
}

algo::MethodReport methodReport(const algo::CalibrationRun& run, const RecordingCalibration& r,
                                const RecordingsCalibrationParams& p) {
  algo::MethodReport m{run, {}, std::nullopt, std::nullopt};
  // --tuples alone has no nominal geometry to compare with.
  if (!r.dataset.empty()) judgeAgainstNominal(m, r.calibration.nominal, p.flags);
  if (r.calibration.agreement && algo::isIntervalMethod(run.method)) {
    if (const auto flag = algo::gyroFlag(run.result, *r.calibration.agreement))
      m.flags.push_back(*flag);
    if (const auto flag = algo::gyroHeadedWheelsFlag(run.result, *r.calibration.agreement))
      m.flags.push_back(*flag);
    if (const auto flag = algo::wheelsScansFlag(run.result, *r.calibration.agreement))
      m.flags.push_back(*flag);
  }
  if (!r.calibration.lidar_mount_from.empty())
    if (const auto flag =
            algo::mountFlag(run.result, r.calibration.T_base_lidar, r.calibration.lidar_mount_from))
      m.flags.push_back(*flag);
  if (r.held_out && run.result.ok) m.validation = validationOf(r, run, p.validate_fraction);
  flagValidation(m);
  return m;
}

// The methods any recording ran, in the order of first appearance.
std::vector<algo::CalibrationMethod> methodsRun(const std::vector<RecordingCalibration>& recs) {
  std::vector<algo::CalibrationMethod> methods;
  for (const RecordingCalibration& r : recs)
    for (const algo::CalibrationRun& run : r.calibration.runs)
      if (std::find(methods.begin(), methods.end(), run.method) == methods.end())
        methods.push_back(run.method);
  return methods;
}

algo::MethodConsistency consistencyOf(const algo::CombinedRun& c) {
  algo::MethodConsistency out{c.run.method, {}};
  const int n = static_cast<int>(c.recordings.size());
  const int size = c.run.result.estimates_mount ? 6 : 3;
  for (int j = 0; j < size; ++j) {
    const Eigen::VectorXd& chi2 = c.estimate.chi2_dof;
    const double value = j < chi2.size() ? chi2(j) : std::numeric_limits<double>::quiet_NaN();
    out.params.push_back({algo::kCalibrationKeys[j], value, n});
  }
  if (n >= 2) {  // Eq. (3) of combine_recordings.hpp: what the drives pin down best
    out.params.push_back({"r_L/b", c.estimate.ratio_chi2_dof(0), n});
    out.params.push_back({"r_R/b", c.estimate.ratio_chi2_dof(1), n});
  }
  return out;
}

// The measured mount every recording shares (one robot, one tf), if they all have one.
const DatasetCalibration* sharedMount(const std::vector<RecordingCalibration>& recs) {
  const DatasetCalibration& first = recs.front().calibration;
  for (const RecordingCalibration& r : recs) {
    const SE2& m = r.calibration.T_base_lidar;
    if (r.calibration.lidar_mount_from.empty() || m.x != first.T_base_lidar.x ||
        m.y != first.T_base_lidar.y || m.yaw != first.T_base_lidar.yaw)
      return nullptr;
  }
  return &first;
}

// The truth every recording shares, if they all have the same one.
std::optional<algo::CalibrationTruth> sharedTruth(const std::vector<RecordingCalibration>& recs) {
  const std::optional<algo::CalibrationTruth>& first = recs.front().calibration.truth;
  for (const RecordingCalibration& r : recs)
    if (!r.calibration.truth || !first || r.calibration.truth->values() != first->values())
      return std::nullopt;
  return first;
}

void combine(const RecordingsCalibrationParams& p, RecordingsCalibration& out) {
  const std::vector<RecordingCalibration>& recs = out.recordings;
  for (const algo::CalibrationMethod method : methodsRun(recs)) {
    out.combined.push_back(algo::combineRuns(method, methodRuns(recs, method), p.combine));
  }
  out.report.combined_truth = sharedTruth(recs);
  for (const algo::CombinedRun& c : out.combined) {
    algo::MethodReport m{
        c.run, {}, combinedValidation(out, c.run, p.validate_fraction), std::nullopt};
    if (!recs.front().dataset.empty())
      judgeAgainstNominal(m, recs.front().calibration.nominal, p.flags);
    if (const DatasetCalibration* given = sharedMount(recs))
      if (const auto flag =
              algo::mountFlag(c.run.result, given->T_base_lidar, given->lidar_mount_from))
        m.flags.push_back(*flag);
    flagValidation(m);
    out.report.combined.push_back(m);
    out.report.consistency.push_back(consistencyOf(c));
  }
}

}  // namespace

void checkSameNominal(const std::vector<std::string>& datasets,
                      const std::optional<DiffDriveParams>& nominal) {
  if (nominal || datasets.size() < 2) return;
  auto nominalOf = [](const std::string& dir) {
    const std::filesystem::path file = std::filesystem::path(dir) / "dataset.json";
    return parseDatasetInfo(readFile(file), file.string()).nominal_geometry;
  };
  const DiffDriveParams first = nominalOf(datasets.front());
  for (std::size_t i = 1; i < datasets.size(); ++i) {
    const DiffDriveParams other = nominalOf(datasets[i]);
    if (!sameGeometry(first, other))
      throw InputError("DATASET", "the recordings' nominal geometries differ: " + datasets.front() +
                                      " has " + geometryText(first) + ", " + datasets[i] + " has " +
                                      geometryText(other) +
                                      "; one robot has one: give it with --nominal r_L,r_R,b");
  }
}

std::optional<algo::ValidationFigures> combinedValidation(const RecordingsCalibration& r,
                                                          const algo::CalibrationRun& combined,
                                                          double fraction) {
  if (!combined.result.ok) return std::nullopt;
  algo::ValidationFigures mean{fraction, {}, {}, std::nullopt};
  if (combined.result.estimates_mount) mean.calibrated_wheels = algo::HeldOutError{};
  int parts = 0;
  for (const RecordingCalibration& rec : r.recordings) {
    if (!rec.held_out) continue;
    const algo::ValidationFigures v = validationOf(rec, combined, fraction);
    accumulate(mean.raw, v.raw);
    accumulate(mean.calibrated, v.calibrated);
    if (v.calibrated_wheels) accumulate(*mean.calibrated_wheels, *v.calibrated_wheels);
    ++parts;
  }
  if (parts == 0) return std::nullopt;
  divide(mean.raw, parts);
  divide(mean.calibrated, parts);
  if (mean.calibrated_wheels) divide(*mean.calibrated_wheels, parts);
  return mean;
}

RecordingsCalibration calibrateRecordings(const RecordingsCalibrationParams& params,
                                          const std::function<void(const std::string&)>& done) {
  RecordingsCalibration out;
  std::vector<std::string> datasets = params.datasets;
  if (datasets.empty()) datasets.push_back(params.base.dataset);
  for (const std::string& dataset : datasets) {
    out.recordings.push_back(calibrateRecording(params, dataset));
    const RecordingCalibration& r = out.recordings.back();
    algo::RecordingReport report{r.dataset,
                                 {},
                                 r.calibration.truth,
                                 r.calibration.agreement,
                                 r.calibration.encoders_from,
                                 r.calibration.clock_offset_s};
    for (const algo::CalibrationRun& run : r.calibration.runs)
      report.methods.push_back(methodReport(run, r, params));
    out.report.recordings.push_back(std::move(report));
    if (done) done(r.dataset);
  }
  if (out.recordings.size() > 1) combine(params, out);
  if (params.leave_one_out && out.recordings.size() > 1)
    out.report.leave_one_out = leaveOneOut(out, params);
  return out;
}

}  // namespace slamprep::eval
