#include "eval/bench/calibration_run.hpp"

#include <algorithm>

#include "algo/calibration/dataset_motion.hpp"
#include "core/error.hpp"
#include "eval/bench/dataset_deskew.hpp"
#include "eval/formats/dataset_io.hpp"

namespace slamprep::eval {
namespace {

bool contains(const std::vector<algo::CalibrationMethod>& methods, algo::CalibrationMethod m) {
  return std::find(methods.begin(), methods.end(), m) != methods.end();
}

std::vector<algo::UmbmarkRun> umbmarkRuns(const DatasetCalibrationParams& params,
                                          const Dataset* dataset) {
  std::vector<algo::UmbmarkRun> runs;
  auto add = [&](const Dataset& d, const std::string& where) {
    if (d.info.scenario.find("umbmark") == std::string::npos) return false;
    const auto run = algo::umbmarkRunFromDataset(d);
    if (!run) throw InputError(where, "UMBmark run needs ground truth and nominal odometry");
    runs.push_back(*run);
    return true;
  };
  if (dataset) add(*dataset, params.dataset);
  for (const std::string& dir : params.squares)
    if (!add(readDataset(dir), dir))
      throw InputError(dir, "--square: not an UMBmark square-run dataset (scenario umbmark_*)");
  return runs;
}

}  // namespace

CalibrationMotion calibrationMotion(const Dataset& dataset,
                                    const CalibrationMotionOptions& options) {
  CalibrationMotion motion;
  if (!options.from_icp) {
    motion.chains.push_back(algo::lidarPosesFromGroundTruth(dataset, options.stamp_is_last_beam));
  } else {
    const std::string name = options.deskew != "auto" ? options.deskew
                             : dataset.imu.empty()    ? "odom-linear"
                                                      : "imu";
    const auto method = algo::parseDeskewMethod(name);
    if (!method) throw InputError("--deskew " + options.deskew, "unknown de-skew method");
    std::vector<Points2> points;  // empty: the scans as measured
    DatasetDeskewOptions deskew = nominalDeskewOptions(dataset);
    deskew.stamp_is_last_beam = options.stamp_is_last_beam;
    if (*method != algo::DeskewMethod::kNone)
      points = correctedPoints(deskewDataset(dataset, *method, deskew));
    algo::ScanMotionParams matching;
    matching.stamp_is_last_beam = options.stamp_is_last_beam;
    motion.matches = algo::matchConsecutiveScans(dataset, matching, points);
    algo::MatchChains chained = algo::chainMatches(motion.matches);
    motion.chains = std::move(chained.chains);
    motion.failed_matches = chained.failed_matches;
  }
  motion.intervals = algo::buildIntervals(dataset, motion.chains, options.intervals);
  return motion;
}

DatasetCalibration calibrateDataset(const DatasetCalibrationParams& params) {
  if (params.dataset.empty() && params.tuples.empty())
    throw InputError("DATASET", "give a dataset directory, --tuples FILE, or both");
  std::optional<Dataset> dataset;
  if (!params.dataset.empty()) dataset = readDataset(params.dataset);
  const Dataset* d = dataset ? &*dataset : nullptr;
  DatasetCalibration out;
  algo::CalibrationInput input;
  if (d) input.nominal = d->info.nominal_geometry;
  if (d && d->info.true_geometry)
    out.truth = algo::CalibrationTruth{*d->info.true_geometry, d->info.T_base_lidar};
  if (contains(params.methods, algo::CalibrationMethod::kUmbmark))
    input.umbmark_runs = umbmarkRuns(params, d);
  const auto& methods = params.methods;
  if (std::any_of(methods.begin(), methods.end(), algo::isIntervalMethod)) {
    if (!params.tuples.empty()) {
      out.intervals.intervals = algo::readIntervalRecords(params.tuples);
    } else {
      if (!params.motion.from_icp && !d->hasTruth())
        throw InputError(params.dataset, "--motion groundtruth: the dataset has no ground truth");
      CalibrationMotion motion = calibrationMotion(*d, params.motion);
      out.intervals = std::move(motion.intervals);
      out.from_motion = true;
      out.failed_matches = motion.failed_matches;
    }
  }
  input.intervals = out.intervals.intervals;
  std::vector<algo::CalibrationMethod> applicable;
  for (const algo::CalibrationMethod m : methods) {
    const auto missing = params.only_applicable ? algo::missingInput(m, input) : std::nullopt;
    if (missing)
      out.not_applicable.push_back({m, *missing});
    else
      applicable.push_back(m);
  }
  out.runs = algo::calibrate(applicable, input, params.params);
  return out;
}

}  // namespace slamprep::eval
