// VICP (Hong et al., ICRA 2010): ICP that also estimates the lidar's velocity during the scan. With
// a constant twist xi over both scans,
//   T_Lref_L(t) = exp(xi (t - t_ref)),
// both scans are de-skewed with xi, the current matched against the previous (point-to-line),
// and the velocity updated from the match, xi = log(T_prevfirst_curfirst) / dt, until the
// scan-end pose settles.
#include "slamprep/algo/deskew/joint_estimate.hpp"

namespace slamprep::algo {
namespace {

/// A scan of a VICP estimate: no base motion, the twist alone moves it.
CorrectedScan constantTwistScan(const LaserScan& scan, const ScanTimes& t) {
  return {&scan, atFirstBeam(t), identityKnot(t.first_s)};
}

}  // namespace

Trajectory vicpKnots(const MethodCall& call) {
  const DeskewInputs& in = call.in;
  call.need(in.previous.has_value(), "the previous scan");
  const PreviousScan& prev = *in.previous;
  const ScanTimes& t = call.t;
  const ScanTimes tp = previousTimes(prev);
  if (t.first_s <= tp.first_s)
    throw Refusal{DeskewRefusal::kBadPreviousScan,
                  "the previous scan is not earlier than this one"};
  if (prev.scan.time_increment_s <= 0.0)
    throw Refusal{DeskewRefusal::kBadPreviousScan, "the previous scan has no beam times"};
  Eigen::Vector3d twist_guess = prev.twist_lidar.value_or(Eigen::Vector3d::Zero());
  if (!in.odometry.empty()) {  // odometry, when there is some, is the better first guess
    const auto T_odom_prev = in.odometry.at(tp.first_s), T_odom_cur = in.odometry.at(t.first_s);
    if (T_odom_prev && T_odom_cur)
      twist_guess = between(*T_odom_prev * in.T_base_lidar, *T_odom_cur * in.T_base_lidar).log() /
                    (t.first_s - tp.first_s);
  }
  const JointEstimate est =
      estimateJointly(constantTwistScan(prev.scan, tp), constantTwistScan(call.scan, t), SE2(),
                      twist_guess, call.params);
  if (!est.match) throw Refusal{DeskewRefusal::kMatchFailed, "vicp: " + est.failure};
  if (!est.failure.empty())
    call.result.warnings.push_back("vicp: " + est.failure + "; kept the round before");
  call.result.match = est.match;
  call.result.rounds = est.rounds;
  call.result.twist_lidar = est.eps;
  return relativeTo(constantTwistKnots(est.eps, t), t.ref_s);
}

MotionEstimate estimateScanMotion(const PreviousScan& previous, const LaserScan& scan,
                                  bool stamp_is_last_beam, const Eigen::Vector3d& twist_guess,
                                  const DeskewParams& params) {
  MotionEstimate out;
  const ScanTimes t = scanTimes(scan, stamp_is_last_beam, ReferenceTime::kFirst);
  const ScanTimes tp = previousTimes(previous);
  if (scan.size() == 0 || previous.scan.size() == 0 || !(scan.time_increment_s > 0.0) ||
      !(previous.scan.time_increment_s > 0.0) || t.first_s <= tp.first_s) {
    out.reason = "needs two non-empty scans in time order with time_increment > 0";
    return out;
  }
  const JointEstimate est = estimateJointly(constantTwistScan(previous.scan, tp),
                                            constantTwistScan(scan, t), SE2(), twist_guess, params);
  out.rounds = est.rounds;
  out.twist_lidar = est.eps;
  if (est.match) out.match = *est.match;
  out.ok = est.match.has_value();
  out.reason = est.failure;
  return out;
}

}  // namespace slamprep::algo
