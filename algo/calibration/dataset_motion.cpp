#include "slamprep/algo/calibration/dataset_motion.hpp"

#include <cassert>
#include <string>

#include "slamprep/core/error.hpp"

namespace slamprep::algo {
namespace {

SE2 odometryGuess(const Dataset& dataset, double t0_s, double t1_s) {
  return odometryLidarMotion(dataset, t0_s, t1_s).value_or(SE2());
}

}  // namespace

std::optional<SE2> odometryLidarMotion(const Dataset& dataset, double t0_s, double t1_s) {
  const auto odom0 = dataset.odom_nominal.at(t0_s), odom1 = dataset.odom_nominal.at(t1_s);
  const SE2& l = dataset.info.T_base_lidar;
  if (!odom0 || !odom1) return std::nullopt;
  return l.inverse() * between(*odom0, *odom1) * l;
}

PoseSeries lidarPosesFromGroundTruth(const Dataset& dataset, bool stamp_is_last_beam) {
  PoseSeries poses;
  for (const ScanRecord& record : dataset.scans) {
    const double t = firstBeamTime(record.scan, stamp_is_last_beam);
    std::optional<SE2> T_world_base;
    if (t == record.scan.stamp_s) T_world_base = record.T_world_base_true;
    if (!T_world_base) T_world_base = dataset.groundtruth.at(t);
    if (!T_world_base) continue;
    if (!poses.empty() && t <= poses.backStamp()) continue;
    poses.push_back(t, *T_world_base * dataset.info.trueMount());
  }
  return poses;
}

std::vector<ScanMatch> matchConsecutiveScans(const Dataset& dataset, const ScanMotionParams& params,
                                             const std::vector<Points2>& scan_points) {
  const bool icp = params.matcher == ScanMatcher::kIcp;
  assert(scan_points.empty() || scan_points.size() == dataset.scans.size());
  std::vector<Points2> raw;
  if (icp && scan_points.empty())
    for (const ScanRecord& record : dataset.scans) raw.push_back(record.scan.points());
  const std::vector<Points2>& points = scan_points.empty() ? raw : scan_points;
  const bool last_beam = params.stamp_is_last_beam;
  std::vector<ScanMatch> out;
  Eigen::Vector3d twist = Eigen::Vector3d::Zero();  // of the last converged match, per second
  for (std::size_t k = 1; k < dataset.scans.size(); ++k) {
    const LaserScan& prev = dataset.scans[k - 1].scan;
    const LaserScan& cur = dataset.scans[k].scan;
    ScanMatch m{k - 1, firstBeamTime(prev, last_beam), firstBeamTime(cur, last_beam), {}};
    const double dt = m.stamp_cur_s - m.stamp_ref_s;
    if (!(dt > 0.0))
      throw InputError("scans.jsonl: scan " + std::to_string(k), "first-beam times not increasing");
    const SE2 guess = params.guess == MotionGuess::kOdometry
                          ? odometryGuess(dataset, m.stamp_ref_s, m.stamp_cur_s)
                          : SE2::exp(twist * dt);
    if (icp) {
      m.match = matchPointToLine(points[k - 1], points[k], guess, params.deskew.icp);
      if (m.match.converged) twist = m.match.T_ref_cur.log() / dt;
    } else {
      const PreviousScan previous{prev, last_beam, std::nullopt, std::nullopt};
      const Eigen::Vector3d twist_guess =
          params.guess == MotionGuess::kOdometry ? Eigen::Vector3d(guess.log() / dt) : twist;
      const MotionEstimate e =
          estimateScanMotion(previous, cur, last_beam, twist_guess, params.deskew);
      m.match = e.match;
      if (e.ok) twist = e.twist_lidar;
      if (!e.ok) m.match.reason = e.reason.empty() ? "no match" : e.reason;
    }
    out.push_back(std::move(m));
  }
  return out;
}

MatchChains chainMatches(const std::vector<ScanMatch>& matches) {
  MatchChains out;
  PoseSeries chain;
  std::vector<std::size_t> scans;
  auto close = [&] {
    if (chain.size() > 1) {
      out.chains.push_back(std::move(chain));
      out.scans.push_back(scans);
    }
    chain = PoseSeries();
    scans.clear();
  };
  for (const ScanMatch& m : matches) {
    if (chain.empty()) {
      chain.push_back(m.stamp_ref_s, SE2());
      scans.push_back(m.ref);
    }
    if (m.match.converged) {
      chain.push_back(m.stamp_cur_s, chain[chain.size() - 1].value * m.match.T_ref_cur);
      scans.push_back(m.ref + 1);
      continue;
    }
    ++out.failed_matches;
    close();
  }
  close();
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
  return UmbmarkRun{
      turned < 0.0,
      *odom0,
      *odom1,
      *true0,
      *true1,
      encoderStepsBetween(dataset.encoders, dataset.info.ticks_per_revolution, t0, t1)};
}

}  // namespace slamprep::algo
