#include "slamprep/eval/metrics/relation_error.hpp"

#include <cmath>
#include <numbers>
#include <optional>

namespace slamprep::eval {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

/// The estimate at t (see RelationErrorParams::max_time_difference_s); nullopt when uncovered.
std::optional<SE2> poseAt(const PoseSeries& estimate, double t, double max_dt) {
  const auto b = estimate.bracket(t);
  if (!b) return std::nullopt;
  const double t_a = estimate[b->index].stamp_s;
  if (t == t_a) return estimate[b->index].value;
  const double t_b = estimate[b->index + 1].stamp_s;
  if (t == t_b) return estimate[b->index + 1].value;
  if (std::max(t - t_a, t_b - t) > max_dt) return std::nullopt;
  return estimate.at(t);
}

RelationStats summarizeSet(const std::vector<double>& translation_m,
                           const std::vector<double>& rotation_deg) {
  std::vector<double> t_sq, r_abs, r_sq;
  for (double e : translation_m) t_sq.push_back(e * e);
  for (double e : rotation_deg) {
    r_abs.push_back(std::abs(e));
    r_sq.push_back(e * e);
  }
  return {summarize(translation_m), summarize(t_sq), summarize(r_abs), summarize(r_sq)};
}

}  // namespace

RelationErrorResult relationError(const PoseSeries& estimate,
                                  const std::vector<PoseRelation>& relations,
                                  const RelationErrorParams& params) {
  RelationErrorResult r;
  r.relations = relations.size();
  std::vector<double> short_t, short_r;
  for (std::size_t k = 0; k < relations.size(); ++k) {
    const PoseRelation& rel = relations[k];
    const auto P_1 = poseAt(estimate, rel.t1_s, params.max_time_difference_s);
    const auto P_2 = poseAt(estimate, rel.t2_s, params.max_time_difference_s);
    if (!P_1 || !P_2) {
      ++r.uncovered;
      continue;
    }
    // E = delta*^-1 delta (the paper's delta ⊖ delta*); |t(E)| = |t(delta) - t(delta*)| since R*^T
    // keeps lengths.
    const SE2 E = between(rel.T_1_2, between(*P_1, *P_2));
    const double e_t = E.translation().norm();
    const double e_r = E.yaw * kDegPerRad;
    r.scored.push_back(k);
    r.translation_errors_m.push_back(e_t);
    r.rotation_errors_deg.push_back(e_r);
    if (std::abs(rel.t2_s - rel.t1_s) < params.short_relation_s) {
      short_t.push_back(e_t);
      short_r.push_back(e_r);
    }
  }
  if (r.scored.empty()) {
    r.reason = relations.empty() ? "no relations"
                                 : "the trajectory covers none of the " +
                                       std::to_string(relations.size()) + " relations' stamps";
    return r;
  }
  r.all = summarizeSet(r.translation_errors_m, r.rotation_errors_deg);
  r.short_span = summarizeSet(short_t, short_r);
  r.short_count = short_t.size();
  r.ok = true;
  return r;
}

}  // namespace slamprep::eval
