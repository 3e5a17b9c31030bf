#include "slamprep/algo/deskew/joint_estimate.hpp"

#include <algorithm>
#include <cmath>

namespace slamprep::algo {
namespace {

/// Valid points of a de-skew as a point set.
Points2 validPoints(const std::vector<std::optional<Eigen::Vector2d>>& p) {
  Points2 out;
  out.reserve(p.size());
  for (const auto& x : p)
    if (x) out.push_back(*x);
  return out;
}

Points2 correctedPoints(const CorrectedScan& s, const Eigen::Vector3d& eps) {
  std::vector<std::optional<Eigen::Vector2d>> p;
  transformBeams(*s.scan, s.t.first_s, correctedKnots(s, eps), p);
  return validPoints(p);
}

bool settled(const SE2& change, const DeskewParams& params) {
  return change.translation().norm() < params.round_tolerance_m &&
         std::abs(change.yaw) < params.round_tolerance_rad;
}

}  // namespace

Trajectory correctedKnots(const CorrectedScan& s, const Eigen::Vector3d& eps) {
  if (s.base.size() == 1) return constantTwistKnots(eps, s.t);
  Trajectory knots = s.base;
  for (Knot& k : knots) k.T = k.T * SE2::exp(eps * (k.stamp_s - s.t.first_s));
  return knots;
}

JointEstimate estimateJointly(const CorrectedScan& prev, const CorrectedScan& cur,
                              const SE2& T_prev_cur_pred, const Eigen::Vector3d& eps_guess,
                              const DeskewParams& params) {
  JointEstimate est;
  est.eps = eps_guess;
  const double dt = cur.t.first_s - prev.t.first_s;
  SE2 T_prev_cur_guess = T_prev_cur_pred * SE2::exp(est.eps * dt);
  for (est.rounds = 1; est.rounds <= params.max_rounds; ++est.rounds) {
    const IcpReference ref(correctedPoints(prev, est.eps), params.icp, true);
    const IcpResult match =
        matchPointToLine(ref, correctedPoints(cur, est.eps), T_prev_cur_guess, params.icp);
    if (!match.converged) {
      est.failure = "ICP failed in round " + std::to_string(est.rounds) + ": " + match.reason;
      break;
    }
    const Eigen::Vector3d eps_new = between(T_prev_cur_pred, match.T_ref_cur).log() / dt;
    const SE2 change = SE2::exp((eps_new - est.eps) * (cur.t.last_s - prev.t.first_s));
    est.eps = eps_new;
    est.match = match;
    T_prev_cur_guess = match.T_ref_cur;
    if (settled(change, params)) break;
  }
  est.rounds = std::min(est.rounds, params.max_rounds);
  return est;
}

ScanTimes previousTimes(const PreviousScan& prev) {
  return atFirstBeam(scanTimes(prev.scan, prev.stamp_is_last_beam, ReferenceTime::kFirst));
}

ScanTimes atFirstBeam(ScanTimes t) {
  t.ref_s = t.first_s;
  return t;
}

}  // namespace slamprep::algo
