#include "algo/deskew/deskew.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <sstream>

#include "algo/deskew/beam_transform.hpp"

namespace slamprep::algo {
namespace {

struct MethodName {
  DeskewMethod method;
  std::string_view name;
};
constexpr std::array<MethodName, 8> kMethodNames{{
    {DeskewMethod::kNone, "none"},
    {DeskewMethod::kOracle, "oracle"},
    {DeskewMethod::kConstVelocity, "const-velocity"},
    {DeskewMethod::kVicp, "vicp"},
    {DeskewMethod::kOdomLinear, "odom-linear"},
    {DeskewMethod::kOdomQuadratic, "odom-quadratic"},
    {DeskewMethod::kImu, "imu"},
    {DeskewMethod::kOdomIcp, "odom-icp"},
}};

std::string fmt(double x) {
  std::ostringstream s;
  s.precision(6);
  s << std::fixed << x;
  return s.str();
}

/// The scan's time span and the reference time.
struct ScanTimes {
  double first_s = 0.0, last_s = 0.0, ref_s = 0.0;
};

ScanTimes scanTimes(const DeskewInput& in) {
  ScanTimes t;
  t.first_s = firstBeamTime(*in.scan, in.stamp_is_last_beam);
  t.last_s = t.first_s + (in.scan->size() - 1) * in.scan->time_increment_s;
  switch (in.reference) {
    case ReferenceTime::kFirst:
      t.ref_s = t.first_s;
      break;
    case ReferenceTime::kMiddle:
      t.ref_s = 0.5 * (t.first_s + t.last_s);
      break;
    case ReferenceTime::kLast:
      t.ref_s = t.last_s;
      break;
  }
  return t;
}

/// Thrown inside this file only: a refusal with its reason (never escapes deskew()).
struct Refusal {
  std::string reason;
};

/// Samples of `poses` (times T_base_lidar) from the one at or before t0 to the one at or after
/// t1: the knots of T_X_L(t). Refuses when they do not bracket [t0, t1] or have a gap inside.
Trajectory lidarKnots(const PoseSeries& poses, const SE2& T_base_lidar, const ScanTimes& t,
                      const LaserScan& scan, bool stamp_is_last_beam, double max_gap_s,
                      std::string_view what) {
  if (auto warning = checkBracketing(scan, stamp_is_last_beam, poses, what))
    throw Refusal{*warning};
  const auto b0 = poses.bracket(t.first_s), b1 = poses.bracket(t.last_s);
  const std::size_t end = poses.size() == 1 ? 0 : std::min(b1->index + 1, poses.size() - 1);
  Trajectory knots;
  knots.reserve(end - b0->index + 1);
  for (std::size_t k = b0->index; k <= end; ++k) {
    if (k > b0->index && poses[k].stamp_s - poses[k - 1].stamp_s > max_gap_s)
      throw Refusal{std::string(what) + " has a gap of " +
                    fmt(poses[k].stamp_s - poses[k - 1].stamp_s) +
                    " s at t = " + fmt(poses[k - 1].stamp_s) +
                    " inside the scan (max_sample_gap_s = " + fmt(max_gap_s) +
                    "); refused, not interpolated across"};
    knots.push_back({poses[k].stamp_s, poses[k].value * T_base_lidar});
  }
  return knots;
}

/// Constant twist over the scan: T_Lref_L(t) = exp(twist (t - t_ref)), as two knots.
Trajectory constantTwistKnots(const Eigen::Vector3d& twist_per_s, const ScanTimes& t) {
  Trajectory knots{{t.first_s, SE2::exp(twist_per_s * (t.first_s - t.ref_s))}};
  if (t.last_s > t.first_s)
    knots.push_back({t.last_s, SE2::exp(twist_per_s * (t.last_s - t.ref_s))});
  return knots;
}

/// The lecture's quadratic: p_s, p_m, p_e interpolated from odometry; per component of
/// q(tau) = p_s^-1 p(t_s + tau), P(tau) = A tau^2 + B tau (+ C = 0) through (0, 0),
/// (tau_e/2, q_m), (tau_e, q_e), Eq.: A = 2 (q_e - 2 q_m) / tau_e^2, B = (4 q_m - q_e) / tau_e;
/// sampled at k + 1 evenly spaced times, linear (geodesic) in between.
Trajectory quadraticKnots(const PoseSeries& odometry, const SE2& T_base_lidar, const ScanTimes& t,
                          int pieces) {
  const double tau_e = t.last_s - t.first_s, t_m = 0.5 * (t.first_s + t.last_s);
  const SE2 p_s = *odometry.at(t.first_s);
  if (tau_e <= 0.0) return {{t.first_s, p_s * T_base_lidar}};  // a single beam
  const Eigen::Vector3d q_m = between(p_s, *odometry.at(t_m)).vector();
  const Eigen::Vector3d q_e = between(p_s, *odometry.at(t.last_s)).vector();
  const Eigen::Vector3d A = 2.0 * (q_e - 2.0 * q_m) / (tau_e * tau_e);
  const Eigen::Vector3d B = (4.0 * q_m - q_e) / tau_e;
  Trajectory knots;
  const int k = std::max(1, pieces);
  for (int j = 0; j <= k; ++j) {
    const double tau = tau_e * j / k;
    const Eigen::Vector3d q = A * tau * tau + B * tau;
    knots.push_back({t.first_s + tau, p_s * SE2(q.x(), q.y(), q.z()) * T_base_lidar});
  }
  return knots;
}

/// Rotation from the gyro (trapezoid between its samples, linear at the scan's ends),
/// translation from odometry: T_k = T_{k-1} exp(rho_odom, dtheta_gyro) at every IMU stamp, with
/// rho_odom the odometry's own twist over the same interval.
Trajectory imuKnots(const ImuLog& imu, const Trajectory& odometry, const SE2& T_base_lidar,
                    const ScanTimes& t, double max_gap_s) {
  auto later = [](double s, const ImuSample& x) { return s < x.stamp_s; };
  const auto after_first = std::upper_bound(imu.begin(), imu.end(), t.first_s, later);
  const auto after_last = std::upper_bound(imu.begin(), imu.end(), t.last_s, later);
  if (imu.empty() || after_first == imu.begin() || after_last == imu.end())
    throw Refusal{"IMU does not bracket the scan [" + fmt(t.first_s) + ", " + fmt(t.last_s) +
                  "] s"};
  for (auto it = after_first - 1; it != after_last; ++it)
    if ((it + 1)->stamp_s - it->stamp_s > max_gap_s)
      throw Refusal{"IMU has a gap of " + fmt((it + 1)->stamp_s - it->stamp_s) + " s at t = " +
                    fmt(it->stamp_s) + " inside the scan; refused, not integrated across"};
  auto gyroAt = [&](std::vector<ImuSample>::const_iterator hi, double s) {  // linear
    const auto lo = hi - 1;
    const double f = (s - lo->stamp_s) / (hi->stamp_s - lo->stamp_s);
    return lo->gyro_z_radps + f * (hi->gyro_z_radps - lo->gyro_z_radps);
  };
  std::vector<std::pair<double, double>> samples;  // (stamp, gyro)
  samples.emplace_back(t.first_s, gyroAt(after_first, t.first_s));
  for (auto it = after_first; it != after_last; ++it)
    if (it->stamp_s > t.first_s) samples.emplace_back(it->stamp_s, it->gyro_z_radps);
  if (t.last_s > samples.back().first) samples.emplace_back(t.last_s, gyroAt(after_last, t.last_s));
  Trajectory knots;
  knots.reserve(samples.size());
  SE2 T_base0_base;
  SE2 T_odom_prev = poseAt(odometry, samples[0].first);
  knots.push_back({samples[0].first, T_base0_base * T_base_lidar});
  for (std::size_t k = 1; k < samples.size(); ++k) {
    const SE2 T_odom_base = poseAt(odometry, samples[k].first);
    const Eigen::Vector3d rho = between(T_odom_prev, T_odom_base).log();
    const double dtheta = 0.5 * (samples[k - 1].second + samples[k].second) *
                          (samples[k].first - samples[k - 1].first);
    T_base0_base = T_base0_base * SE2::exp({rho.x(), rho.y(), dtheta});
    knots.push_back({samples[k].first, T_base0_base * T_base_lidar});
    T_odom_prev = T_odom_base;
  }
  return knots;
}

/// Valid points of a de-skew as a point set.
Points2 validPoints(const std::vector<std::optional<Eigen::Vector2d>>& p) {
  Points2 out;
  out.reserve(p.size());
  for (const auto& x : p)
    if (x) out.push_back(*x);
  return out;
}

bool settled(const SE2& change, const DeskewParams& params) {
  return change.translation().norm() < params.round_tolerance_m &&
         std::abs(change.yaw) < params.round_tolerance_rad;
}

/// One scan of a joint estimate: its beams, first-beam time, and base trajectory T_L0_L(t)
/// (odometry, or a single identity knot) that the correction exp(eps (t - t_first)) multiplies.
struct CorrectedScan {
  const LaserScan* scan = nullptr;
  ScanTimes t;
  Trajectory base;
};

/// base(t_k) * exp(eps (t_k - t_first)) at every knot; with a single identity base knot, a
/// constant twist eps over the whole scan.
Trajectory correctedKnots(const CorrectedScan& s, const Eigen::Vector3d& eps) {
  if (s.base.size() == 1) return constantTwistKnots(eps, s.t);
  Trajectory knots = s.base;
  for (Knot& k : knots) k.T = k.T * SE2::exp(eps * (k.stamp_s - s.t.first_s));
  return knots;
}

Points2 correctedPoints(const CorrectedScan& s, const Eigen::Vector3d& eps) {
  std::vector<std::optional<Eigen::Vector2d>> p;
  transformBeams(*s.scan, s.t.first_s, correctedKnots(s, eps), p);
  return validPoints(p);
}

/// The outcome of a joint estimate: the correction rate and the last good match.
struct JointEstimate {
  Eigen::Vector3d eps = Eigen::Vector3d::Zero();
  std::optional<IcpResult> match;
  int rounds = 0;
  std::string failure;  ///< the ICP failure that ended it, if one did
};

/// Both scans corrected by the same rate eps, the current one matched against the previous;
/// E = T_pred^-1 T_icp (T_pred: the motion between first beams the bases predict) is the
/// correction accumulated over dt, eps = log(E) / dt (Eq. of the lecture's last slide, with the
/// error growing linearly in time); repeat until the scan-end pose settles.
JointEstimate estimateJointly(const CorrectedScan& prev, const CorrectedScan& cur,
                              const SE2& T_pred, const Eigen::Vector3d& eps_guess,
                              const DeskewParams& params) {
  JointEstimate est;
  est.eps = eps_guess;
  const double dt = cur.t.first_s - prev.t.first_s;
  SE2 guess = T_pred * SE2::exp(est.eps * dt);
  for (est.rounds = 1; est.rounds <= params.max_rounds; ++est.rounds) {
    const IcpReference ref(correctedPoints(prev, est.eps), params.icp, true);
    const IcpResult match = matchPointToLine(ref, correctedPoints(cur, est.eps), guess, params.icp);
    if (!match.converged) {
      est.failure = "ICP failed in round " + std::to_string(est.rounds) + ": " + match.reason;
      break;
    }
    const Eigen::Vector3d eps_new = between(T_pred, match.T_ref_cur).log() / dt;
    const SE2 change = SE2::exp((eps_new - est.eps) * (cur.t.last_s - prev.t.first_s));
    est.eps = eps_new;
    est.match = match;
    guess = match.T_ref_cur;
    if (settled(change, params)) break;
  }
  est.rounds = std::min(est.rounds, params.max_rounds);
  return est;
}

/// The same times with the reference moved to the first beam (joint estimates work there).
ScanTimes atFirstBeam(ScanTimes t) {
  t.ref_s = t.first_s;
  return t;
}

/// The previous scan's times (always relative to its first beam).
ScanTimes previousTimes(const PreviousScan& prev) {
  DeskewInput in;
  in.scan = &prev.scan;
  in.stamp_is_last_beam = prev.stamp_is_last_beam;
  ScanTimes t = scanTimes(in);
  t.ref_s = t.first_s;
  return t;
}

Trajectory identityKnot(double t) {
  return {{t, SE2()}};
}

/// VICP: a constant twist over both scans, estimated jointly with the match.
Trajectory vicpKnots(const DeskewInput& in, const ScanTimes& t, const DeskewParams& params,
                     DeskewResult& result) {
  const PreviousScan& prev = *in.previous;
  const ScanTimes tp = previousTimes(prev);
  if (t.first_s <= tp.first_s) throw Refusal{"the previous scan is not earlier than this one"};
  if (prev.scan.time_increment_s <= 0.0) throw Refusal{"the previous scan has no beam times"};
  Eigen::Vector3d guess = prev.twist_lidar.value_or(Eigen::Vector3d::Zero());
  if (in.odometry) {  // odometry, when there is some, is the better first guess
    const auto T0 = in.odometry->at(tp.first_s), T1 = in.odometry->at(t.first_s);
    if (T0 && T1)
      guess =
          between(*T0 * in.T_base_lidar, *T1 * in.T_base_lidar).log() / (t.first_s - tp.first_s);
  }
  const CorrectedScan p{&prev.scan, tp, identityKnot(tp.first_s)};
  const CorrectedScan c{in.scan, atFirstBeam(t), identityKnot(t.first_s)};
  const JointEstimate est = estimateJointly(p, c, SE2(), guess, params);
  if (!est.match) throw Refusal{"vicp: " + est.failure};
  if (!est.failure.empty())
    result.warnings.push_back("vicp: " + est.failure + "; kept the round before");
  result.match = est.match;
  result.rounds = est.rounds;
  result.twist_lidar = est.eps;
  return constantTwistKnots(est.eps, t);
}

/// Odometry + ICP (the lecture's last slide): odometry de-skew, ICP against the previous scan,
/// the odometry error spread linearly over the beams, iterated; both scans share the correction.
Trajectory odomIcpKnots(const DeskewInput& in, const ScanTimes& t, const DeskewParams& params,
                        DeskewResult& result) {
  const PreviousScan& prev = *in.previous;
  const ScanTimes tp = previousTimes(prev);
  if (t.first_s <= tp.first_s) throw Refusal{"the previous scan is not earlier than this one"};
  auto odomBase = [&](const LaserScan& scan, bool last_stamp, const ScanTimes& times) {
    return relativeTo(lidarKnots(*in.odometry, in.T_base_lidar, times, scan, last_stamp,
                                 params.max_sample_gap_s, "odometry"),
                      times.first_s);
  };
  const CorrectedScan c{in.scan, atFirstBeam(t), odomBase(*in.scan, in.stamp_is_last_beam, t)};
  std::optional<CorrectedScan> p;
  try {
    p = CorrectedScan{&prev.scan, tp, odomBase(prev.scan, prev.stamp_is_last_beam, tp)};
  } catch (const Refusal& r) {
    result.warnings.push_back("odom-icp: previous scan unusable (" + r.reason +
                              "); fell back to odometry alone (odom-linear)");
  }
  if (!p) return c.base;
  const SE2 T_pred = between(*in.odometry->at(tp.first_s) * in.T_base_lidar,
                             *in.odometry->at(t.first_s) * in.T_base_lidar);
  const JointEstimate est = estimateJointly(
      *p, c, T_pred, prev.odometry_error_per_s.value_or(Eigen::Vector3d::Zero()), params);
  result.rounds = est.rounds;
  if (!est.failure.empty())
    result.warnings.push_back(
        "odom-icp: " + est.failure + "; " +
        (est.match ? "kept the round before" : "fell back to odometry alone (odom-linear)"));
  if (!est.match) return c.base;
  result.match = est.match;
  result.odometry_error_per_s = est.eps;
  return correctedKnots(c, est.eps);
}

/// T_Lref_L knots for the method, or a Refusal.
Trajectory methodKnots(DeskewMethod method, const DeskewInput& in, const ScanTimes& t,
                       const DeskewParams& params, DeskewResult& result) {
  auto need = [&](const void* p, const char* what) {
    if (!p)
      throw Refusal{std::string(deskewMethodName(method)) + " needs " + what + ", none was given"};
  };
  auto odomKnots = [&](const PoseSeries& poses, std::string_view what) {
    return lidarKnots(poses, in.T_base_lidar, t, *in.scan, in.stamp_is_last_beam,
                      params.max_sample_gap_s, what);
  };
  switch (method) {
    case DeskewMethod::kNone:
      return identityKnot(t.ref_s);
    case DeskewMethod::kOracle:
      need(in.oracle, "ground-truth poses (the dataset has no truth)");
      return relativeTo(odomKnots(*in.oracle, "ground truth"), t.ref_s);
    case DeskewMethod::kOdomLinear:
      need(in.odometry, "odometry");
      return relativeTo(odomKnots(*in.odometry, "odometry"), t.ref_s);
    case DeskewMethod::kOdomQuadratic:
      need(in.odometry, "odometry");
      odomKnots(*in.odometry, "odometry");  // bracketing and gap checks only
      return relativeTo(quadraticKnots(*in.odometry, in.T_base_lidar, t, params.quadratic_pieces),
                        t.ref_s);
    case DeskewMethod::kImu: {
      need(in.odometry, "odometry (for translation)");
      need(in.imu, "an IMU log");
      // The odometry samples around the scan (base frame), checked for bracketing and gaps.
      const Trajectory odom = lidarKnots(*in.odometry, SE2(), t, *in.scan, in.stamp_is_last_beam,
                                         params.max_sample_gap_s, "odometry");
      return relativeTo(imuKnots(*in.imu, odom, in.T_base_lidar, t, params.max_sample_gap_s),
                        t.ref_s);
    }
    case DeskewMethod::kConstVelocity:
      if (!in.previous || !in.previous->twist_lidar) {
        result.warnings.push_back("const-velocity: no previous motion yet; scan left as measured");
        return constantTwistKnots(Eigen::Vector3d::Zero(), t);
      }
      return constantTwistKnots(*in.previous->twist_lidar, t);
    case DeskewMethod::kVicp:
      need(in.previous, "the previous scan");
      return relativeTo(vicpKnots(in, t, params, result), t.ref_s);
    case DeskewMethod::kOdomIcp:
      need(in.odometry, "odometry");
      if (!in.previous) {
        result.warnings.push_back("odom-icp: no previous scan; de-skewed by odometry alone");
        return relativeTo(odomKnots(*in.odometry, "odometry"), t.ref_s);
      }
      return relativeTo(odomIcpKnots(in, t, params, result), t.ref_s);
  }
  throw Refusal{"unknown method"};
}

}  // namespace

const std::vector<DeskewMethod>& allDeskewMethods() {
  static const std::vector<DeskewMethod> all = [] {
    std::vector<DeskewMethod> v;
    for (const auto& m : kMethodNames) v.push_back(m.method);
    return v;
  }();
  return all;
}

std::string_view deskewMethodName(DeskewMethod method) {
  for (const auto& m : kMethodNames)
    if (m.method == method) return m.name;
  return "unknown";
}

std::optional<DeskewMethod> parseDeskewMethod(std::string_view name) {
  for (const auto& m : kMethodNames)
    if (m.name == name) return m.method;
  return std::nullopt;
}

bool deskewMethodUsesPreviousScan(DeskewMethod method) {
  return method == DeskewMethod::kConstVelocity || method == DeskewMethod::kVicp ||
         method == DeskewMethod::kOdomIcp;
}

std::string_view referenceTimeName(ReferenceTime reference) {
  switch (reference) {
    case ReferenceTime::kFirst:
      return "first";
    case ReferenceTime::kMiddle:
      return "middle";
    case ReferenceTime::kLast:
      return "last";
  }
  return "unknown";
}

std::optional<ReferenceTime> parseReferenceTime(std::string_view name) {
  for (ReferenceTime r : {ReferenceTime::kFirst, ReferenceTime::kMiddle, ReferenceTime::kLast})
    if (referenceTimeName(r) == name) return r;
  return std::nullopt;
}

double firstBeamTime(const LaserScan& scan, bool stamp_is_last_beam) {
  if (!stamp_is_last_beam || scan.size() == 0) return scan.stamp_s;
  return scan.stamp_s - (scan.size() - 1) * scan.time_increment_s;
}

std::optional<std::string> checkBracketing(const LaserScan& scan, bool stamp_is_last_beam,
                                           const PoseSeries& poses, std::string_view what) {
  const double duration = (scan.size() > 0 ? scan.size() - 1 : 0) * scan.time_increment_s;
  const double first = firstBeamTime(scan, stamp_is_last_beam), last = first + duration;
  if (poses.covers(first) && poses.covers(last)) return std::nullopt;
  std::string message =
      std::string(what) + " does not bracket the scan [" + fmt(first) + ", " + fmt(last) + "] s";
  message += poses.empty() ? " (it is empty)"
                           : " (it covers [" + fmt(poses.frontStamp()) + ", " +
                                 fmt(poses.backStamp()) + "] s)";
  const double other_first = firstBeamTime(scan, !stamp_is_last_beam);
  if (poses.covers(other_first) && poses.covers(other_first + duration))
    message += stamp_is_last_beam
                   ? "; it would if the stamp marked the first beam: is stamp_is_last_beam wrong?"
                   : "; it would if the stamp marked the last beam: set stamp_is_last_beam";
  return message;
}

MotionEstimate estimateScanMotion(const PreviousScan& previous, const LaserScan& scan,
                                  bool stamp_is_last_beam, const Eigen::Vector3d& twist_guess,
                                  const DeskewParams& params) {
  MotionEstimate out;
  DeskewInput in;
  in.scan = &scan;
  in.stamp_is_last_beam = stamp_is_last_beam;
  const ScanTimes t = scanTimes(in);
  const ScanTimes tp = previousTimes(previous);
  if (scan.size() == 0 || previous.scan.size() == 0 || !(scan.time_increment_s > 0.0) ||
      !(previous.scan.time_increment_s > 0.0) || t.first_s <= tp.first_s) {
    out.reason = "needs two non-empty scans in time order with time_increment > 0";
    return out;
  }
  const JointEstimate est =
      estimateJointly({&previous.scan, tp, identityKnot(tp.first_s)},
                      {&scan, atFirstBeam(t), identityKnot(t.first_s)}, SE2(), twist_guess, params);
  out.rounds = est.rounds;
  out.twist_lidar = est.eps;
  if (est.match) out.match = *est.match;
  out.ok = est.match.has_value();
  out.reason = est.failure;
  return out;
}

DeskewResult deskew(DeskewMethod method, const DeskewInput& in, const DeskewParams& params) {
  DeskewResult result;
  if (!in.scan) {
    result.reason = "no scan given";
    return result;
  }
  const LaserScan& scan = *in.scan;
  if (scan.size() == 0) {
    result.reason = "the scan has no beams";
    return result;
  }
  if (!(scan.time_increment_s > 0.0) || !std::isfinite(scan.time_increment_s)) {
    result.reason = "time_increment is " + fmt(scan.time_increment_s) +
                    ": the beam times are unknown, so the scan cannot be de-skewed";
    return result;
  }
  const ScanTimes t = scanTimes(in);
  result.first_beam_s = t.first_s;
  result.reference_s = t.ref_s;
  try {
    result.T_ref_lidar = methodKnots(method, in, t, params, result);
    transformBeams(scan, t.first_s, result.T_ref_lidar, result.p_ref);
    // The first-beam frame seen from the reference frame is the knots' value at t_first.
    result.T_first_ref = poseAt(result.T_ref_lidar, t.first_s).inverse();
  } catch (const Refusal& refusal) {
    result.p_ref.clear();
    result.T_ref_lidar.clear();
    result.reason = refusal.reason;
    return result;
  }
  if (params.repack) {
    result.repacked = repackScan(scan, result.p_ref);
    result.repacked.stamp_s = t.ref_s;
    result.repacked.time_increment_s = 0.0;
  }
  result.ok = true;
  return result;
}

}  // namespace slamprep::algo
