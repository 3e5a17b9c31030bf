// Odometry + ICP (the lecture's last slide): de-skew with odometry; assume the odometry error
// over the scan is linear in time, a correction exp(eps (t - t_first)) in the lidar frame,
//   T_L0_L(t) = T_L0_L,odom(t) exp(eps (t - t_first));
// match the current scan against the previous one by ICP (both corrected with the same eps, so
// the correction's error does not feed back), take the difference from the odometry's
// prediction E = T_prev_cur_pred^-1 T_prev_cur_icp as the error accumulated between the first
// beams, eps = log(E) / dt, spread it over the beams linearly, and iterate until it settles.
#include "slamprep/algo/deskew/joint_estimate.hpp"

namespace slamprep::algo {

Trajectory odomIcpKnots(const MethodCall& call) {
  const DeskewInputs& in = call.in;
  const ScanTimes& t = call.t;
  if (!in.previous) {
    call.result.warnings.push_back("odom-icp: no previous scan; de-skewed by odometry alone");
    return relativeTo(lidarKnots(call, in.odometry, in.T_base_lidar, "odometry"), t.ref_s);
  }
  const PreviousScan& prev = *in.previous;
  const ScanTimes tp = previousTimes(prev);
  if (t.first_s <= tp.first_s)
    throw Refusal{DeskewRefusal::kBadPreviousScan,
                  "the previous scan is not earlier than this one"};
  // T_L0_L(t) by odometry for one scan, seen from its first beam.
  auto odometryScan = [&](const LaserScan& scan, bool last_stamp, const ScanTimes& times) {
    return CorrectedScan{
        &scan, atFirstBeam(times),
        relativeTo(lidarKnots(in.odometry, in.T_base_lidar, times, scan, last_stamp,
                              call.params.max_sample_gap_s, "odometry"),
                   times.first_s)};
  };
  const CorrectedScan cur = odometryScan(call.scan, in.stamp_is_last_beam, t);
  std::optional<CorrectedScan> previous;
  try {
    previous = odometryScan(prev.scan, prev.stamp_is_last_beam, tp);
  } catch (const Refusal& r) {
    call.result.warnings.push_back("odom-icp: previous scan unusable (" + r.reason +
                                   "); fell back to odometry alone (odom-linear)");
  }
  if (!previous) return relativeTo(cur.base, t.ref_s);
  const SE2 T_prev_cur_pred = between(*in.odometry.at(tp.first_s) * in.T_base_lidar,
                                      *in.odometry.at(t.first_s) * in.T_base_lidar);
  const JointEstimate est =
      estimateJointly(*previous, cur, T_prev_cur_pred,
                      prev.odometry_error_per_s.value_or(Eigen::Vector3d::Zero()), call.params);
  call.result.rounds = est.rounds;
  if (!est.failure.empty())
    call.result.warnings.push_back(
        "odom-icp: " + est.failure + "; " +
        (est.match ? "kept the round before" : "fell back to odometry alone (odom-linear)"));
  if (!est.match) return relativeTo(cur.base, t.ref_s);
  call.result.match = est.match;
  call.result.odometry_error_per_s = est.eps;
  return relativeTo(correctedKnots(cur, est.eps), t.ref_s);
}

}  // namespace slamprep::algo
