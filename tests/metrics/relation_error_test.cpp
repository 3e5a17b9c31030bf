// The relation metric of Kümmerle et al. 2009 (eval/metrics/relation_error.hpp) on synthetic
// trajectories whose errors are known in closed form.
#include "slamprep/eval/metrics/relation_error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace slamprep::eval {
namespace {

constexpr double kDegree = std::numbers::pi / 180;

// A constant-twist drive (a circle of radius 4 m) sampled at 10 Hz for 60 s: geodesic
// interpolation between its samples is exact, so any stamp inside it has a true pose.
SE2 circleAt(double t) {
  return SE2::exp(Eigen::Vector3d(0.8, 0.0, 0.2) * t);
}

PoseSeries circle() {
  PoseSeries s;
  for (int k = 0; k <= 600; ++k) s.push_back(k / 10.0, circleAt(k / 10.0));  // exact 12.0 etc.
  return s;
}

// Relations of the truth: every 0.5 s a pair 1 s apart and one 10 s apart, with stamps between
// samples (0.5 k + 0.03) so that interpolation is exercised.
std::vector<PoseRelation> relationsOf(double t_end) {
  std::vector<PoseRelation> out;
  for (double t1 = 0.03; t1 + 10 < t_end; t1 += 0.5)
    for (double dt : {1.0, 10.0})
      out.push_back({t1, t1 + dt, between(circleAt(t1), circleAt(t1 + dt))});
  return out;
}

TEST(RelationError, TheTrajectoryTheRelationsWereMadeFromScoresZero) {
  const auto relations = relationsOf(60);
  const RelationErrorResult r = relationError(circle(), relations);
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_EQ(r.scored.size(), relations.size());
  EXPECT_EQ(r.uncovered, 0u);
  EXPECT_EQ(r.short_count, relations.size() / 2);  // the 1 s ones
  // Exact up to rounding of poses of ~8 m: well below 1e-12 m and 1e-10 deg.
  EXPECT_LT(r.all.translation_m.max, 1e-12);
  EXPECT_LT(r.all.rotation_deg.max, 1e-10);
}

// The estimate jumps at t_c = 30.05 s: from then on P = C Q with a world transform C. Relations
// with both stamps on one side see no error; across the jump E = delta*^-1 delta = Q2^-1 C Q2,
// rotation yaw(C) and translation R2^T (R_C p2 + t_C - p2).
struct Jump {
  std::vector<PoseRelation> relations;
  RelationErrorResult result;
  std::vector<Eigen::Vector2d> across_p2;  // Q(t2) of the relations across the jump
  std::size_t across_short = 0;
};

Jump scoreJump(const SE2& C) {
  Jump j;
  PoseSeries estimate;
  const PoseSeries truth = circle();
  for (const auto& s : truth.samples())
    estimate.push_back(s.stamp_s, s.stamp_s >= 30.05 ? C * s.value : s.value);
  for (double t1 = 0.0; t1 + 10 <= 60; t1 += 1.0)  // on samples: no interpolation across t_c
    for (double dt : {1.0, 10.0}) {
      j.relations.push_back({t1, t1 + dt, between(circleAt(t1), circleAt(t1 + dt))});
      if (t1 < 30.05 && t1 + dt >= 30.05) {
        j.across_p2.push_back(circleAt(t1 + dt).translation());
        j.across_short += dt < 5;
      }
    }
  j.result = relationError(estimate, j.relations);
  return j;
}

TEST(RelationError, AShiftInTheEstimateGivesItsLengthOnEveryRelationAcrossIt) {
  const Jump j = scoreJump(SE2(0.3, 0.0, 0.0));
  const RelationErrorResult& r = j.result;
  ASSERT_TRUE(r.ok) << r.reason;
  ASSERT_EQ(j.relations.size(), 102u);  // t1 = 0..50, 1 s and 10 s apart
  ASSERT_EQ(j.across_p2.size(), 11u);   // t1 = 30 (1 s) and t1 = 21..30 (10 s)
  ASSERT_EQ(j.across_short, 1u);
  // Bernoulli values: a share p of the relations has error e, the rest 0: mean p e,
  // population std e sqrt(p (1 - p)), max e; squares likewise with e^2.
  const double p = 11.0 / 102.0, e = 0.3;
  EXPECT_NEAR(r.all.translation_m.mean, p * e, 1e-12);
  EXPECT_NEAR(r.all.translation_m.std, e * std::sqrt(p * (1 - p)), 1e-12);
  EXPECT_NEAR(r.all.translation_m.max, e, 1e-12);
  EXPECT_NEAR(r.all.translation_sq_m2.mean, p * e * e, 1e-12);
  EXPECT_NEAR(r.all.translation_sq_m2.std, e * e * std::sqrt(p * (1 - p)), 1e-12);
  EXPECT_LT(r.all.rotation_deg.max, 1e-10);
  // The short subset (51 relations 1 s apart) holds one of them.
  EXPECT_EQ(r.short_count, 51u);
  EXPECT_NEAR(r.short_span.translation_m.mean, e / 51.0, 1e-12);
  EXPECT_NEAR(r.short_span.translation_m.max, e, 1e-12);
}

TEST(RelationError, ATurnOfTheEstimateGivesItsAngleAndTheChordOfEachRelation) {
  // C turns by 2 deg about the world origin: rotation error 2 deg across the jump; translation
  // |R p2 - p2| = 2 |p2| sin(1 deg), p2 on the circle around (0, 4).
  const double phi = 2.0;
  const Jump j = scoreJump(SE2(0.0, 0.0, phi * kDegree));
  const RelationErrorResult& r = j.result;
  ASSERT_TRUE(r.ok) << r.reason;
  const double p = 11.0 / 102.0;
  EXPECT_NEAR(r.all.rotation_deg.mean, p * phi, 1e-10);
  EXPECT_NEAR(r.all.rotation_deg.std, phi * std::sqrt(p * (1 - p)), 1e-10);
  EXPECT_NEAR(r.all.rotation_deg.max, phi, 1e-10);
  EXPECT_NEAR(r.all.rotation_sq_deg2.mean, p * phi * phi, 1e-9);
  double sum = 0.0, largest = 0.0;
  for (const auto& p2 : j.across_p2) {
    const double chord = 2 * p2.norm() * std::sin(phi / 2 * kDegree);
    sum += chord;
    largest = std::max(largest, chord);
  }
  EXPECT_NEAR(r.all.translation_m.mean, sum / 102.0, 1e-12);
  EXPECT_NEAR(r.all.translation_m.max, largest, 1e-12);
}

TEST(RelationError, StampsOutsideOrInGapsAreSkippedAndCounted) {
  PoseSeries estimate = circle();
  std::vector<PoseRelation> relations = {
      {-1.0, 2.0, between(circleAt(0), circleAt(2))},         // before the first sample
      {59.0, 61.0, between(circleAt(59), circleAt(60))},      // after the last
      {10.0, 12.05, between(circleAt(10), circleAt(12.05))},  // between samples: interpolated
      {12.0, 10.0, between(circleAt(12), circleAt(10))},      // t2 < t1 is a relation too
  };
  RelationErrorParams p;
  RelationErrorResult r = relationError(estimate, relations, p);
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.uncovered, 2u);
  EXPECT_EQ(r.scored, (std::vector<std::size_t>{2, 3}));
  EXPECT_LT(r.all.translation_m.max, 1e-12);
  // Samples 0.1 s apart: a stamp 0.05 s from both is refused with a window of 0.04 s, while a
  // stamp on a sample always matches.
  p.max_time_difference_s = 0.04;
  r = relationError(estimate, relations, p);
  EXPECT_EQ(r.scored, (std::vector<std::size_t>{3}));
  // Nothing covered at all is a failure with a reason.
  r = relationError(estimate, {relations[0]}, p);
  EXPECT_FALSE(r.ok);
  EXPECT_EQ(r.reason, "the trajectory covers none of the 1 relations' stamps");
}

}  // namespace
}  // namespace slamprep::eval
