#include "slamprep/eval/metrics/trajectory_error.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

namespace slamprep::eval {
namespace {

constexpr double kDegPerRad = 180.0 / std::numbers::pi;

// A curvy ground truth at 100 Hz for 20 s: positions of order 5 m.
PoseSeries curvyTruth() {
  PoseSeries gt;
  for (int k = 0; k <= 2000; ++k) {
    const double t = 0.01 * k;
    gt.push_back(t, SE2(5 * std::sin(0.2 * t), 3 - 3 * std::cos(0.3 * t), 0.4 * t));
  }
  return gt;
}

PoseSeries transformed(const PoseSeries& s, const SE2& left, const SE2& right = SE2()) {
  PoseSeries out;
  for (const auto& x : s.samples()) out.push_back(x.stamp_s, left * x.value * right);
  return out;
}

TEST(AlignRigid2D, RecoversAKnownRigidTransformExactly) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-10, 10);
  const SE2 T(1.5, -2.0, 2.7);
  Points2 p, q;
  for (int i = 0; i < 50; ++i) {
    p.emplace_back(u(rng), u(rng));
    q.push_back(T * p.back());
  }
  const AlignmentResult r = alignRigid2D(p, q);
  ASSERT_TRUE(r.ok) << r.reason;
  // Exact up to rounding: coordinates of ~10 m, sums of 50 terms -> well below 1e-12.
  EXPECT_NEAR(r.T_ref_est.x, 1.5, 1e-12);
  EXPECT_NEAR(r.T_ref_est.y, -2.0, 1e-12);
  EXPECT_NEAR(r.T_ref_est.yaw, 2.7, 1e-13);
  EXPECT_LT(r.rmse_m, 1e-12);
}

TEST(AlignRigid2D, IsALeastSquaresMinimumWithNoise) {
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(-5, 5);
  std::normal_distribution<double> noise(0.0, 0.05);
  const SE2 T(-0.3, 0.8, -1.1);
  Points2 p, q;
  for (int i = 0; i < 30; ++i) {
    p.emplace_back(u(rng), u(rng));
    q.push_back(T * p.back() + Eigen::Vector2d(noise(rng), noise(rng)));
  }
  const AlignmentResult r = alignRigid2D(p, q);
  ASSERT_TRUE(r.ok);
  auto cost = [&](const SE2& X) {
    double c = 0;
    for (std::size_t i = 0; i < p.size(); ++i) c += (q[i] - X * p[i]).squaredNorm();
    return c;
  };
  const double best = cost(r.T_ref_est);
  EXPECT_NEAR(std::sqrt(best / p.size()), r.rmse_m, 1e-12);
  for (const Eigen::Vector3d& d : {Eigen::Vector3d(1e-4, 0, 0), Eigen::Vector3d(0, -1e-4, 0),
                                   Eigen::Vector3d(0, 0, 1e-4), Eigen::Vector3d(0, 0, -1e-4)})
    EXPECT_GT(cost(r.T_ref_est * SE2::exp(d)), best);
}

TEST(AlignRigid2D, RefusesDegenerateInput) {
  EXPECT_FALSE(alignRigid2D({{1, 1}}, {{0, 0}}).ok);
  EXPECT_FALSE(alignRigid2D({{1, 1}, {1, 1}}, {{0, 0}, {1, 0}}).ok);
  EXPECT_FALSE(alignRigid2D({{1, 1}, {2, 1}}, {{0, 0}}).ok);
}

TEST(Ape, ConstantWorldOffsetGivesThatOffsetWithoutAlignment) {
  const PoseSeries gt = curvyTruth();
  const PoseSeries est = transformed(gt, SE2(0.3, -0.4, 0.0));
  const ApeResult r = absolutePoseError(est, gt, {.align = false});
  ASSERT_TRUE(r.ok) << r.reason;
  EXPECT_EQ(r.matched, gt.size());
  // |(0.3, -0.4)| = 0.5 for every pose.
  EXPECT_NEAR(r.translation_m.rmse, 0.5, 1e-12);
  EXPECT_NEAR(r.translation_m.min, 0.5, 1e-12);
  EXPECT_NEAR(r.translation_m.max, 0.5, 1e-12);
  EXPECT_NEAR(r.rotation_deg.max, 0.0, 1e-12);
  // With alignment the offset is found and removed.
  const ApeResult aligned = absolutePoseError(est, gt);
  ASSERT_TRUE(aligned.ok);
  EXPECT_LT(aligned.translation_m.max, 1e-12);
  EXPECT_NEAR(aligned.T_ref_est.x, -0.3, 1e-12);
  EXPECT_NEAR(aligned.T_ref_est.y, 0.4, 1e-12);
}

TEST(Ape, ConstantBodyOffsetGivesItsNormAndAngle) {
  const PoseSeries gt = curvyTruth();
  const PoseSeries est = transformed(gt, SE2(), SE2(0.06, 0.08, 0.02));
  const ApeResult r = absolutePoseError(est, gt, {.align = false});
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.translation_m.mean, 0.1, 1e-12);
  EXPECT_NEAR(r.translation_m.std, 0.0, 1e-12);
  EXPECT_NEAR(r.rotation_deg.mean, 0.02 * kDegPerRad, 1e-10);
  EXPECT_NEAR(r.rotation_deg.p95, 0.02 * kDegPerRad, 1e-10);
}

TEST(Ape, AlignmentRemovesAGlobalRotationAboutTheOrigin) {
  const PoseSeries gt = curvyTruth();
  const PoseSeries est = transformed(gt, SE2(2.0, 1.0, -2.0));
  const ApeResult raw = absolutePoseError(est, gt, {.align = false});
  ASSERT_EQ(raw.translation_errors_m.size(), gt.size());
  for (std::size_t i = 0; i < gt.size(); ++i) {  // unaligned: |T t_i - t_i| per pose
    const Eigen::Vector2d t = gt[i].value.translation();
    ASSERT_NEAR(raw.translation_errors_m[i], (SE2(2.0, 1.0, -2.0) * t - t).norm(), 1e-12);
  }
  EXPECT_NEAR(raw.rotation_deg.mean, 2.0 * kDegPerRad, 1e-9);
  const ApeResult r = absolutePoseError(est, gt);
  ASSERT_TRUE(r.ok);
  EXPECT_LT(r.translation_m.max, 1e-11);
  EXPECT_LT(r.rotation_deg.max, 1e-9);
}

// Dead reckoning in its own odom frame: origin alignment puts the first poses together and keeps
// the drift, which a full alignment would partly absorb.
TEST(Ape, OriginAlignmentKeepsDriftThatFullAlignmentAbsorbs) {
  const PoseSeries gt = curvyTruth();
  const SE2 T_odom_world = gt[0].value.inverse();  // odometry starts at its own identity
  PoseSeries odom;
  for (const auto& s : gt.samples())  // heading error growing 0.01 rad per second
    odom.push_back(s.stamp_s, T_odom_world * s.value * SE2(0.0, 0.0, 0.01 * s.stamp_s));
  const ApeResult origin = absolutePoseError(odom, gt, {.align = false, .align_origin = true});
  ASSERT_TRUE(origin.ok) << origin.reason;
  // The positions coincide (the body rotation moves none), only the heading drifts.
  EXPECT_LT(origin.translation_m.max, 1e-12);
  EXPECT_NEAR(origin.rotation_deg.max, 0.2 * kDegPerRad, 1e-9);
  EXPECT_NEAR(origin.rotation_errors_deg.front(), 0.0, 1e-12);

  // A world-frame drift of the positions: 1 cm per second along x.
  PoseSeries drifting;
  for (const auto& s : gt.samples())
    drifting.push_back(s.stamp_s, T_odom_world * SE2(0.01 * s.stamp_s, 0.0, 0.0) * s.value);
  const ApeResult kept = absolutePoseError(drifting, gt, {.align = false, .align_origin = true});
  ASSERT_TRUE(kept.ok);
  EXPECT_NEAR(kept.translation_errors_m.front(), 0.0, 1e-12);
  EXPECT_NEAR(kept.translation_m.max, 0.2, 1e-12);  // 20 s at 1 cm/s
  EXPECT_LT(absolutePoseError(drifting, gt).translation_m.max, kept.translation_m.max);
}

TEST(Association, InterpolatesBetweenReferenceSamplesAndCountsTheUnmatched) {
  // Reference moves at a constant twist, so geodesic interpolation is exact.
  PoseSeries gt;
  for (int k = 0; k <= 10; ++k) gt.push_back(0.1 * k, SE2::exp({0.2 * k, 0.0, 0.05 * k}));
  gt.push_back(5.0, SE2(0, 0, 0));  // a 3.9 s gap after t = 1.0
  PoseSeries est;
  for (int k = 0; k < 10; ++k) {
    const double t = 0.05 + 0.1 * k;
    est.push_back(t, SE2::exp({2.0 * t, 0.0, 0.5 * t}));
  }
  est.push_back(3.0, SE2());  // inside the gap: must not be interpolated
  est.push_back(5.0, SE2());  // exactly on a reference stamp
  est.push_back(6.0, SE2());  // after the reference: no extrapolation
  const AssociatedPoses a = associateByTime(est, gt, 0.06);
  EXPECT_EQ(a.estimate.size(), 11u);
  EXPECT_EQ(a.unmatched, 2u);
  const ApeResult r = absolutePoseError(est, gt, {.align = false, .max_time_difference_s = 0.06});
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.unmatched, 2u);
  EXPECT_LT(r.translation_m.max, 1e-12);
  EXPECT_LT(r.rotation_deg.max, 1e-10);
  // A tolerance below half the sample spacing rejects every midpoint.
  EXPECT_EQ(associateByTime(est, gt, 0.04).estimate.size(), 1u);
}

TEST(Ape, RefusesWhenNothingMatches) {
  PoseSeries gt, est;
  gt.push_back(0.0, SE2());
  gt.push_back(1.0, SE2());
  est.push_back(2.0, SE2());
  const ApeResult r = absolutePoseError(est, gt);
  EXPECT_FALSE(r.ok);
  EXPECT_FALSE(r.reason.empty());
}

TEST(Rpe, OfATrajectoryAgainstItselfIsZero) {
  const PoseSeries gt = curvyTruth();
  for (RpeParams p : {RpeParams{}, RpeParams{.delta = 10}, RpeParams{.delta = 7, .all_pairs = true},
                      RpeParams{.delta = 1.0, .unit = DeltaUnit::kMeters},
                      RpeParams{.delta = 0.5, .unit = DeltaUnit::kMeters, .all_pairs = true}}) {
    const RpeResult r = relativePoseError(gt, gt, p);
    ASSERT_TRUE(r.ok) << r.reason;
    EXPECT_GT(r.pairs, 10u);
    // Q_ij^-1 Q_ij is the identity up to rounding of the products (coordinates ~5 m).
    EXPECT_LT(r.translation_m.max, 1e-13);
    EXPECT_LT(r.rotation_deg.max, 1e-12);
  }
}

TEST(Rpe, IsInvariantToARigidTransformOfTheEstimate) {
  const PoseSeries gt = curvyTruth();
  const RpeResult r = relativePoseError(transformed(gt, SE2(3, -1, 1.2)), gt, {.delta = 5});
  ASSERT_TRUE(r.ok);
  EXPECT_LT(r.translation_m.max, 1e-12);
  EXPECT_LT(r.rotation_deg.max, 1e-10);
}

// Reference: 1 m per frame along x, one frame per second. Estimate: 1.1 m per frame.
struct Straight {
  PoseSeries gt, est;
  Straight() {
    for (int k = 0; k < 10; ++k) {
      gt.push_back(k, SE2(k, 0, 0));
      est.push_back(k, SE2(1.1 * k, 0, 0));
    }
  }
};

TEST(Rpe, ScaleErrorGivesTenPercentOfTheDelta) {
  const Straight s;
  // E = (Q_i^-1 Q_j)^-1 (P_i^-1 P_j) = (-d, 0, 0) (1.1 d, 0, 0) = (0.1 d, 0, 0).
  RpeResult r = relativePoseError(s.est, s.gt, {.delta = 1});
  ASSERT_TRUE(r.ok);
  EXPECT_EQ(r.pairs, 9u);
  EXPECT_NEAR(r.translation_m.min, 0.1, 1e-14);
  EXPECT_NEAR(r.translation_m.max, 0.1, 1e-14);
  r = relativePoseError(s.est, s.gt, {.delta = 3});
  EXPECT_EQ(r.pairs, 3u);  // (0,3) (3,6) (6,9)
  EXPECT_NEAR(r.translation_m.mean, 0.3, 1e-14);
  r = relativePoseError(s.est, s.gt, {.delta = 3, .all_pairs = true});
  EXPECT_EQ(r.pairs, 7u);  // i = 0..6
  // Metres, evo's consecutive mode: marks where the path since the previous mark reaches 2.5 m.
  // Estimate path (evo's default) 1.1 m per frame: 3.3 m at frames 3, 6, 9 -> (3,6), (6,9).
  using Pairs = std::vector<std::pair<std::size_t, std::size_t>>;
  r = relativePoseError(s.est, s.gt, {.delta = 2.5, .unit = DeltaUnit::kMeters});
  EXPECT_EQ(r.index_pairs, (Pairs{{3, 6}, {6, 9}}));
  EXPECT_NEAR(r.translation_m.max, 0.3, 1e-14);
  EXPECT_EQ(r.rotation_deg.max, 0.0);
  // On the reference (1 m per frame), 2 m is reached exactly at frames 2, 4, 6, 8.
  r = relativePoseError(s.est, s.gt,
                        {.delta = 2.0, .unit = DeltaUnit::kMeters, .pairs_from_reference = true});
  EXPECT_EQ(r.index_pairs, (Pairs{{2, 4}, {4, 6}, {6, 8}}));
  EXPECT_NEAR(r.translation_m.mean, 0.2, 1e-14);
  // All pairs: from every i the nearest path to 2 m is exactly 2 frames on (i = 0..7).
  r = relativePoseError(
      s.est, s.gt,
      {.delta = 2.0, .unit = DeltaUnit::kMeters, .all_pairs = true, .pairs_from_reference = true});
  EXPECT_EQ(r.pairs, 8u);
  EXPECT_NEAR(r.translation_m.max, 0.2, 1e-14);
}

TEST(Rpe, AllPairsInMetresTakeTheNearestPathWithinTolerance) {
  // Path lengths 0, 1, 1.9, 3.15. delta 2, tol 0.2: from 0 the nearest is 1.9 (j = 2); from 1,
  // 0.9 or 2.15 -> j = 3; from 2, 1.25 is 0.75 off -> none.
  const std::vector<SE2> poses = {SE2(0, 0, 0), SE2(1, 0, 0), SE2(1.9, 0, 0), SE2(3.15, 0, 0)};
  const auto pairs = rpePairs(poses, {.delta = 2.0, .unit = DeltaUnit::kMeters, .all_pairs = true});
  EXPECT_EQ(pairs, (std::vector<std::pair<std::size_t, std::size_t>>{{0, 2}, {1, 3}}));
}

TEST(Rpe, HeadingDriftGivesItsAngle) {
  // Estimate turns 0.01 rad per frame more than the straight reference.
  const Straight s;
  PoseSeries est;
  for (const auto& x : s.est.samples())
    est.push_back(x.stamp_s, SE2(x.value.x, 0, 0.01 * x.stamp_s));
  const RpeResult r = relativePoseError(est, s.gt, {.delta = 2});
  ASSERT_TRUE(r.ok);
  EXPECT_NEAR(r.rotation_deg.min, 0.02 * kDegPerRad, 1e-12);
  EXPECT_NEAR(r.rotation_deg.max, 0.02 * kDegPerRad, 1e-12);
}

TEST(Rpe, RefusesBadDeltaAndTooShortTrajectories) {
  const Straight s;
  EXPECT_FALSE(relativePoseError(s.est, s.gt, {.delta = 0}).ok);
  EXPECT_FALSE(relativePoseError(s.est, s.gt, {.delta = std::nan("")}).ok);
  EXPECT_FALSE(relativePoseError(s.est, s.gt, {.delta = 20}).ok);
  EXPECT_FALSE(relativePoseError(s.est, s.gt, {.delta = 100, .unit = DeltaUnit::kMeters}).ok);
  // All pairs in metres: 2.5 m is 0.5 m from the nearest pose on a 1 m grid, beyond 10 %.
  EXPECT_FALSE(relativePoseError(s.est, s.gt,
                                 {.delta = 2.5,
                                  .unit = DeltaUnit::kMeters,
                                  .all_pairs = true,
                                  .pairs_from_reference = true})
                   .ok);
}

}  // namespace
}  // namespace slamprep::eval
