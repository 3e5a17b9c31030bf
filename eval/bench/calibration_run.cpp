#include "eval/bench/calibration_run.hpp"

#include "algo/calibration/dataset_motion.hpp"
#include "core/error.hpp"
#include "eval/bench/dataset_deskew.hpp"

namespace slamprep::eval {

CalibrationMotion calibrationMotion(const Dataset& dataset,
                                    const CalibrationMotionOptions& options) {
  CalibrationMotion motion;
  if (!options.from_icp) {
    motion.chains.push_back(algo::lidarPosesFromGroundTruth(dataset));
  } else {
    const std::string name = options.deskew != "auto" ? options.deskew
                             : dataset.imu.empty()    ? "odom-linear"
                                                      : "imu";
    const auto method = algo::parseDeskewMethod(name);
    if (!method) throw InputError("--deskew " + options.deskew, "unknown de-skew method");
    std::vector<Points2> points;  // empty: the scans as measured
    if (*method != algo::DeskewMethod::kNone)
      points = correctedPoints(deskewDataset(dataset, *method, nominalDeskewOptions(dataset)));
    motion.matches = algo::matchConsecutiveScans(dataset, {}, points);
    algo::MatchChains chained = algo::chainMatches(motion.matches);
    motion.chains = std::move(chained.chains);
    motion.failed_matches = chained.failed_matches;
  }
  motion.intervals = algo::buildIntervals(dataset, motion.chains, options.intervals);
  return motion;
}

}  // namespace slamprep::eval
