#include "algo/calibration/dataset_motion.hpp"

#include <cassert>

namespace slamprep::algo {

PoseSeries lidarPosesFromGroundTruth(const Dataset& dataset) {
  PoseSeries poses;
  for (const ScanRecord& record : dataset.scans) {
    const double t = record.scan.stamp_s;
    std::optional<SE2> T_world_base = record.T_world_base_true;
    if (!T_world_base) T_world_base = dataset.groundtruth.at(t);
    if (!T_world_base) continue;
    if (!poses.empty() && t <= poses.backStamp()) continue;
    poses.push_back(t, *T_world_base * dataset.info.T_base_lidar);
  }
  return poses;
}

IcpChains lidarPosesFromIcp(const Dataset& dataset, const IcpParams& params) {
  std::vector<Points2> raw;
  raw.reserve(dataset.scans.size());
  for (const ScanRecord& record : dataset.scans) raw.push_back(record.scan.points());
  return lidarPosesFromIcp(dataset, raw, params);
}

IcpChains lidarPosesFromIcp(const Dataset& dataset, const std::vector<Points2>& scan_points,
                            const IcpParams& params) {
  assert(scan_points.size() == dataset.scans.size());
  IcpChains out;
  const SE2& l = dataset.info.T_base_lidar;
  PoseSeries chain;
  Points2 prev_points;
  double prev_stamp = 0.0;
  for (std::size_t k = 0; k < dataset.scans.size(); ++k) {
    const double t = dataset.scans[k].scan.stamp_s;
    Points2 points = scan_points[k];
    const auto odom_prev = dataset.odom_nominal.at(prev_stamp);
    const auto odom_cur = dataset.odom_nominal.at(t);
    if (!chain.empty() && t > chain.backStamp()) {
      const SE2 guess =
          odom_prev && odom_cur ? l.inverse() * between(*odom_prev, *odom_cur) * l : SE2();
      const IcpResult match = matchPointToLine(prev_points, points, guess, params);
      if (match.converged) {
        chain.push_back(t, chain[chain.size() - 1].value * match.T_ref_cur);
      } else {
        ++out.failed_matches;
        if (chain.size() > 1) out.chains.push_back(chain);
        chain = PoseSeries();
      }
    }
    if (chain.empty()) chain.push_back(t, SE2());
    prev_points = std::move(points);
    prev_stamp = t;
  }
  if (chain.size() > 1) out.chains.push_back(chain);
  return out;
}

IntervalSet buildIntervals(const Dataset& dataset, const std::vector<PoseSeries>& chains,
                           const IntervalParams& params) {
  IntervalSet all;
  for (const PoseSeries& chain : chains) {
    IntervalSet set =
        buildIntervals(dataset.encoders, dataset.info.ticks_per_revolution, chain, params);
    all.intervals.insert(all.intervals.end(), set.intervals.begin(), set.intervals.end());
    all.dropped_standstill += set.dropped_standstill;
    all.dropped_uncovered += set.dropped_uncovered;
  }
  return all;
}

std::optional<UmbmarkRun> umbmarkRunFromDataset(const Dataset& dataset) {
  const PoseSeries& truth = dataset.groundtruth;
  if (truth.size() < 2) return std::nullopt;
  const double t0 = std::max(truth.frontStamp(), dataset.odom_nominal.empty()
                                                     ? truth.frontStamp()
                                                     : dataset.odom_nominal.frontStamp());
  const double t1 =
      std::min(truth.backStamp(),
               dataset.odom_nominal.empty() ? truth.backStamp() : dataset.odom_nominal.backStamp());
  const auto odom0 = dataset.odom_nominal.at(t0), odom1 = dataset.odom_nominal.at(t1);
  const auto true0 = truth.at(t0), true1 = truth.at(t1);
  if (!odom0 || !odom1 || !true0 || !true1) return std::nullopt;
  double turned = 0.0;  // unwrapped heading change of the true path
  for (std::size_t i = 1; i < truth.size(); ++i)
    turned += normalizeAngle(truth[i].value.yaw - truth[i - 1].value.yaw);
  return UmbmarkRun{turned < 0.0, *odom0, *odom1, *true0, *true1};
}

}  // namespace slamprep::algo
