#include "slamprep/eval/metrics/trajectory_error.hpp"

#include <cmath>
#include <numbers>

#include "slamprep/core/rigid_alignment.hpp"

namespace slamprep::eval {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// |t(E)| and |angle(E)| in degrees of a pose error E.
void appendError(const SE2& E, std::vector<double>& translation_m,
                 std::vector<double>& rotation_deg) {
  translation_m.push_back(E.translation().norm());
  rotation_deg.push_back(std::abs(E.yaw) * kDegPerRad);
}

bool referenceClose(const PoseSeries& reference, const Bracket& b, double t, double max_dt) {
  const double t_a = reference[b.index].stamp_s;
  if (t == t_a || reference.size() == 1) return t == t_a;
  const double t_b = reference[b.index + 1].stamp_s;
  return t == t_b || std::max(t - t_a, t_b - t) <= max_dt;
}

std::vector<double> pathLengths(const std::vector<SE2>& poses) {
  std::vector<double> s(poses.size(), 0.0);
  for (std::size_t k = 1; k < poses.size(); ++k)
    s[k] = s[k - 1] + (poses[k].translation() - poses[k - 1].translation()).norm();
  return s;
}

std::vector<std::pair<std::size_t, std::size_t>> framePairs(std::size_t n, std::size_t d,
                                                            bool all_pairs) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t i = 0; i + d < n; i += all_pairs ? 1 : d) pairs.emplace_back(i, i + d);
  return pairs;
}

using IndexPairs = std::vector<std::pair<std::size_t, std::size_t>>;

IndexPairs consecutive(const std::vector<std::size_t>& marks) {
  IndexPairs pairs;
  for (std::size_t k = 1; k < marks.size(); ++k) pairs.emplace_back(marks[k - 1], marks[k]);
  return pairs;
}

// Marks where the path walked since the previous mark reaches delta (evo's consecutive mode).
IndexPairs pathSegments(const std::vector<SE2>& poses, double delta_m) {
  std::vector<std::size_t> marks;
  double walked = 0.0;
  for (std::size_t k = 1; k < poses.size(); ++k) {
    walked += (poses[k].translation() - poses[k - 1].translation()).norm();
    if (walked >= delta_m) {
      marks.push_back(k);
      walked = 0.0;
    }
  }
  return consecutive(marks);
}

// For every i, the j whose path length from i is nearest to delta, within the tolerance.
IndexPairs pathAllPairs(const std::vector<SE2>& poses, double delta_m, double tol_m) {
  const std::vector<double> s = pathLengths(poses);
  IndexPairs pairs;
  std::size_t hi = 0;  // first j with s[j] - s[i] >= delta; never moves back as i grows
  for (std::size_t i = 0; i < s.size(); ++i) {
    hi = std::max(hi, i);
    while (hi < s.size() && s[hi] - s[i] < delta_m) ++hi;
    std::size_t best = hi;
    if (hi == s.size() || (hi > i && delta_m - (s[hi - 1] - s[i]) <= s[hi] - s[i] - delta_m))
      best = hi - 1;  // the pose just short of delta is at least as near
    if (best > i && std::abs(s[best] - s[i] - delta_m) <= tol_m) pairs.emplace_back(i, best);
  }
  return pairs;
}

}  // namespace

AssociatedPoses associateByTime(const PoseSeries& estimate, const PoseSeries& reference,
                                double max_time_difference_s) {
  AssociatedPoses out;
  for (const auto& sample : estimate.samples()) {
    const auto b = reference.bracket(sample.stamp_s);
    if (!b || !referenceClose(reference, *b, sample.stamp_s, max_time_difference_s)) {
      ++out.unmatched;
      continue;
    }
    out.stamps_s.push_back(sample.stamp_s);
    out.estimate.push_back(sample.value);
    out.reference.push_back(*reference.at(sample.stamp_s));
  }
  return out;
}

AlignmentResult alignRigid2D(const Points2& p_est, const Points2& q_ref) {
  AlignmentResult r;
  const RigidAlignment2D solved = solveRigid2D(p_est, q_ref);
  if (!solved.T_q_p) {
    r.reason = "estimate positions: " + solved.reason;
    return r;
  }
  r.T_ref_est = *solved.T_q_p;
  double sq = 0.0;
  for (std::size_t i = 0; i < p_est.size(); ++i)
    sq += (q_ref[i] - r.T_ref_est * p_est[i]).squaredNorm();
  r.rmse_m = std::sqrt(sq / static_cast<double>(p_est.size()));
  r.ok = true;
  return r;
}

ApeResult absolutePoseError(const PoseSeries& estimate, const PoseSeries& reference,
                            const ApeParams& params) {
  ApeResult r;
  const AssociatedPoses a = associateByTime(estimate, reference, params.max_time_difference_s);
  r.unmatched = a.unmatched;
  if (a.estimate.empty()) {
    r.reason = "no estimate pose has a reference within the time tolerance";
    return r;
  }
  if (params.align) {
    Points2 p, q;
    for (std::size_t i = 0; i < a.estimate.size(); ++i) {
      p.push_back(a.estimate[i].translation());
      q.push_back(a.reference[i].translation());
    }
    const AlignmentResult alignment = alignRigid2D(p, q);
    if (!alignment.ok) {
      r.reason = "alignment: " + alignment.reason;
      return r;
    }
    r.T_ref_est = alignment.T_ref_est;
  } else if (params.align_origin) {
    r.T_ref_est = a.reference.front() * a.estimate.front().inverse();
  }
  for (std::size_t i = 0; i < a.estimate.size(); ++i) {
    const SE2 E = a.reference[i].inverse() * (r.T_ref_est * a.estimate[i]);  // E_i = Q_i^-1 P_i
    appendError(E, r.translation_errors_m, r.rotation_errors_deg);
  }
  r.stamps_s = a.stamps_s;
  r.matched = a.estimate.size();
  r.translation_m = summarize(r.translation_errors_m);
  r.rotation_deg = summarize(r.rotation_errors_deg);
  r.ok = r.translation_m.ok && r.rotation_deg.ok;
  if (!r.ok) r.reason = "errors: " + r.translation_m.reason + r.rotation_deg.reason;
  return r;
}

std::vector<std::pair<std::size_t, std::size_t>> rpePairs(const std::vector<SE2>& poses,
                                                          const RpeParams& params) {
  if (params.unit == DeltaUnit::kFrames) {
    const auto d = static_cast<std::size_t>(std::max(1.0, std::round(params.delta)));
    return framePairs(poses.size(), d, params.all_pairs);
  }
  if (params.all_pairs)
    return pathAllPairs(poses, params.delta, params.rel_delta_tol * params.delta);
  return pathSegments(poses, params.delta);
}

RpeResult relativePoseError(const PoseSeries& estimate, const PoseSeries& reference,
                            const RpeParams& params) {
  RpeResult r;
  if (!(params.delta > 0.0) || !std::isfinite(params.delta)) {
    r.reason = "delta must be a positive number";
    return r;
  }
  const AssociatedPoses a = associateByTime(estimate, reference, params.max_time_difference_s);
  r.unmatched = a.unmatched;
  r.index_pairs = rpePairs(params.pairs_from_reference ? a.reference : a.estimate, params);
  if (r.index_pairs.empty()) {
    r.reason =
        "no pose pair is delta apart (" + std::to_string(a.estimate.size()) + " associated poses)";
    return r;
  }
  for (const auto& [i, j] : r.index_pairs) {
    const SE2 Q_ij = between(a.reference[i], a.reference[j]);
    const SE2 P_ij = between(a.estimate[i], a.estimate[j]);
    appendError(Q_ij.inverse() * P_ij, r.translation_errors_m, r.rotation_errors_deg);
  }
  r.pairs = r.index_pairs.size();
  r.translation_m = summarize(r.translation_errors_m);
  r.rotation_deg = summarize(r.rotation_errors_deg);
  r.ok = r.translation_m.ok && r.rotation_deg.ok;
  if (!r.ok) r.reason = "errors: " + r.translation_m.reason + r.rotation_deg.reason;
  return r;
}

}  // namespace slamprep::eval
