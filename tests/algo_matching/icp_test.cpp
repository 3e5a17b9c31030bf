#include "slamprep/algo/matching/icp.hpp"

#include <gtest/gtest.h>

#include <random>

#include "slamprep/tests/algo_deskew/synthetic_world.hpp"

namespace slamprep::algo {
namespace {

using slamprep::testing::castRay;
using slamprep::testing::roomWorld;

/// A scan taken from one pose (no motion during the scan), 720 beams, optional range noise.
Points2 staticScan(const SE2& T_world_lidar, double noise_m = 0.0, unsigned seed = 1) {
  const auto world = roomWorld();
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, noise_m);
  Points2 points;
  for (int i = 0; i < 720; ++i) {
    const double a = -M_PI + i * 2.0 * M_PI / 720;
    double r = castRay(world, T_world_lidar.translation(), T_world_lidar.yaw + a, 30.0);
    if (!std::isfinite(r)) continue;
    if (noise_m > 0.0) r += noise(rng);
    points.push_back(r * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  return points;
}

struct Case {
  SE2 T_world_ref, T_world_cur;
};

std::vector<Case> cases() {
  return {{SE2(0.0, 0.0, 0.0), SE2(0.10, 0.03, 0.08)},
          {SE2(-1.0, 0.5, 1.0), SE2(-0.85, 0.62, 1.15)},
          {SE2(0.5, -1.0, -2.0), SE2(0.42, -1.12, -2.1)},
          {SE2(-2.0, 1.5, 3.0), SE2(-1.9, 1.45, 2.93)}};
}

// Noiseless scans of a polygon world: every reference line fitted inside one wall is exact, so
// point-to-line's fixed point is the true pose up to the few corner fits that trimming leaves.
// With the step tolerance tightened to 1e-8 m / 1e-9 rad (the defaults, 0.1 mm / 1e-5 rad, are
// sized for 1 cm range noise), 1e-5 m / 1e-6 rad must hold.
TEST(Icp, PointToLineRecoversKnownTransformAndInverse) {
  IcpParams tight;
  tight.translation_tolerance_m = 1e-8;
  tight.rotation_tolerance_rad = 1e-9;
  for (const Case& c : cases()) {
    const SE2 T_ref_cur = between(c.T_world_ref, c.T_world_cur);
    const Points2 ref = staticScan(c.T_world_ref), cur = staticScan(c.T_world_cur);
    const IcpResult fwd = matchPointToLine(ref, cur, SE2(), tight);
    ASSERT_TRUE(fwd.converged) << fwd.reason;
    EXPECT_NEAR(fwd.T_ref_cur.x, T_ref_cur.x, 1e-5);
    EXPECT_NEAR(fwd.T_ref_cur.y, T_ref_cur.y, 1e-5);
    EXPECT_NEAR(fwd.T_ref_cur.yaw, T_ref_cur.yaw, 1e-6);
    const IcpResult inv = matchPointToLine(cur, ref, SE2(), tight);
    ASSERT_TRUE(inv.converged) << inv.reason;
    const SE2 T_cur_ref = T_ref_cur.inverse();
    EXPECT_NEAR(inv.T_ref_cur.x, T_cur_ref.x, 1e-5);
    EXPECT_NEAR(inv.T_ref_cur.y, T_cur_ref.y, 1e-5);
    EXPECT_NEAR(inv.T_ref_cur.yaw, T_cur_ref.yaw, 1e-6);
    // With the defaults: within the 0.1 mm / 1e-5 rad they stop at, plus the same margin.
    const IcpResult loose = matchPointToLine(ref, cur, SE2(), {});
    ASSERT_TRUE(loose.converged) << loose.reason;
    EXPECT_LT(between(T_ref_cur, loose.T_ref_cur).translation().norm(), 2e-4);
    EXPECT_GT(fwd.inliers, 500u);
    EXPECT_LT(fwd.rms_residual_m, 1e-3);
  }
}

// Point-to-point converges to a pose biased by the sampling: a current point is pulled towards a
// reference sample up to half the beam spacing away along the wall (r * 2pi/720 / 2 ~ 2.6 cm at
// 6 m). These pulls cancel on average over ~600 pairs; we allow 1 cm and 5 mrad, a quarter of
// the spacing, and check the forward and inverse matches agree with each other as well.
TEST(Icp, PointToPointRecoversKnownTransformAndInverse) {
  for (const Case& c : cases()) {
    const SE2 T_ref_cur = between(c.T_world_ref, c.T_world_cur);
    const Points2 ref = staticScan(c.T_world_ref), cur = staticScan(c.T_world_cur);
    const IcpResult fwd = matchPointToPoint(ref, cur, SE2(), {});
    ASSERT_TRUE(fwd.converged) << fwd.reason;
    EXPECT_NEAR(fwd.T_ref_cur.x, T_ref_cur.x, 1e-2);
    EXPECT_NEAR(fwd.T_ref_cur.y, T_ref_cur.y, 1e-2);
    EXPECT_NEAR(fwd.T_ref_cur.yaw, T_ref_cur.yaw, 5e-3);
    const IcpResult inv = matchPointToPoint(cur, ref, SE2(), {});
    ASSERT_TRUE(inv.converged) << inv.reason;
    const SE2 loop = fwd.T_ref_cur * inv.T_ref_cur;  // should be the identity
    EXPECT_LT(loop.translation().norm(), 2e-2);
    EXPECT_LT(std::abs(loop.yaw), 1e-2);
  }
}

TEST(Icp, ClosedFormStepIsExactForKnownCorrespondences) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  const SE2 T(0.7, -1.2, 2.5);
  Points2 p, q;
  for (int i = 0; i < 50; ++i) {
    p.emplace_back(u(rng), u(rng));
    q.push_back(T * p.back());
  }
  const auto est = alignPointToPoint(p, q);
  ASSERT_TRUE(est);
  // Closed form on exact data: only rounding, ~1e-15 per operation times the 5 m lever.
  EXPECT_NEAR(est->x, T.x, 1e-12);
  EXPECT_NEAR(est->y, T.y, 1e-12);
  EXPECT_NEAR(est->yaw, T.yaw, 1e-12);
}

TEST(Icp, PointToLineNeedsFewerIterationsThanPointToPoint) {
  int iterations_p2l = 0, iterations_p2p = 0;
  for (const Case& c : cases()) {
    const Points2 ref = staticScan(c.T_world_ref, 0.01, 5),
                  cur = staticScan(c.T_world_cur, 0.01, 6);
    IcpParams params;
    params.max_iterations = 1000;  // point-to-point converges slowly: let it finish
    const IcpResult p2l = matchPointToLine(ref, cur, SE2(), params);
    const IcpResult p2p = matchPointToPoint(ref, cur, SE2(), params);
    ASSERT_TRUE(p2l.converged) << p2l.reason;
    ASSERT_TRUE(p2p.converged) << p2p.reason;
    EXPECT_LT(p2l.iterations, p2p.iterations);
    iterations_p2l += p2l.iterations;
    iterations_p2p += p2p.iterations;
  }
  // Point-to-line's step is (nearly) Newton's; point-to-point converges linearly along walls.
  EXPECT_LT(2 * iterations_p2l, iterations_p2p);
}

// With 1 cm range noise the estimate's spread is what the covariance claims: the sample
// variances over 40 noise draws must lie within a factor 2.5 of the predicted ones (a
// chi-square with 40 dof stays within [0.5, 1.6] of its mean at 99.9%; the rest is the model's
// approximations: one sigma for all beams whatever their incidence, corner fits).
TEST(Icp, CovarianceMatchesTheSpreadUnderRangeNoise) {
  const Case c = cases()[1];
  const SE2 T_ref_cur = between(c.T_world_ref, c.T_world_cur);
  const Points2 ref = staticScan(c.T_world_ref);
  const IcpReference reference(ref, {}, true);
  Eigen::Matrix3d predicted = Eigen::Matrix3d::Zero(), spread = Eigen::Matrix3d::Zero();
  const int draws = 40;
  for (int k = 0; k < draws; ++k) {
    const IcpResult r =
        matchPointToLine(reference, staticScan(c.T_world_cur, 0.01, 100 + k), SE2(), {});
    ASSERT_TRUE(r.converged) << r.reason;
    const Eigen::Vector3d e(r.T_ref_cur.x - T_ref_cur.x, r.T_ref_cur.y - T_ref_cur.y,
                            normalizeAngle(r.T_ref_cur.yaw - T_ref_cur.yaw));
    spread += e * e.transpose() / draws;
    predicted += r.covariance / draws;
  }
  for (int i = 0; i < 3; ++i) {
    EXPECT_GT(spread(i, i), predicted(i, i) / 2.5) << i;
    EXPECT_LT(spread(i, i), predicted(i, i) * 2.5) << i;
  }
}

// Scan-to-keyframe: one prepared keyframe, scans from poses up to 30 cm / 0.2 rad away matched
// against it with the previous result as the guess (as a tracker does); 1 cm noise gives ~1 mm
// and ~0.3 mrad precision (see the covariance test), asserted at 5 mm / 2 mrad.
TEST(Icp, ScanToKeyframeTracksAgainstOnePreparedReference) {
  const SE2 T_world_kf(0.2, -0.4, 0.6);
  const IcpReference keyframe(staticScan(T_world_kf, 0.01, 50), {}, true);
  SE2 guess;
  for (int k = 1; k <= 6; ++k) {
    const SE2 T_world_cur = T_world_kf * SE2(0.05 * k, 0.01 * k, 0.033 * k);
    const IcpResult r =
        matchPointToLine(keyframe, staticScan(T_world_cur, 0.01, 50 + k), guess, {});
    ASSERT_TRUE(r.converged) << k << ": " << r.reason;
    const SE2 err = between(between(T_world_kf, T_world_cur), r.T_ref_cur);
    EXPECT_LT(err.translation().norm(), 0.005) << k;
    EXPECT_LT(std::abs(err.yaw), 0.002) << k;
    guess = r.T_ref_cur;
  }
}

// Clutter the reference does not have (a person, a chair leg: 80 points 10-30 cm in front of
// the walls, inside the 0.5 m correspondence gate) pulls an ungated least-squares match by
// millimetres; the robust gate drops exactly them and recovers the noiseless pose to 1e-5 m.
TEST(Icp, RobustGateDropsClutterThatBiasesAnUngatedMatch) {
  const Case c = cases()[0];
  const SE2 T_ref_cur = between(c.T_world_ref, c.T_world_cur);
  const Points2 ref = staticScan(c.T_world_ref);
  Points2 cur = staticScan(c.T_world_cur);
  const std::size_t walls = cur.size();
  for (std::size_t i = 0; i < 80; ++i) {  // every 4th of the first 320 points, pulled inward
    const Eigen::Vector2d& p = cur[4 * i];
    cur.push_back(p * (1.0 - (0.1 + 0.2 * static_cast<double>(i % 5) / 4.0) / p.norm()));
  }
  IcpParams tight;
  tight.translation_tolerance_m = 1e-8;
  tight.rotation_tolerance_rad = 1e-9;
  tight.trim_fraction = 0.0;
  const auto error = [&](double sigmas) {
    IcpParams params = tight;
    params.outlier_sigmas = sigmas;
    const IcpResult r = matchPointToLine(ref, cur, SE2(), params);
    EXPECT_TRUE(r.converged) << r.reason;
    return std::pair(between(T_ref_cur, r.T_ref_cur).translation().norm(), r.inliers);
  };
  const auto [ungated_m, ungated_inliers] = error(0.0);
  EXPECT_GT(ungated_m, 1e-3);
  EXPECT_GT(ungated_inliers, walls);  // the clutter took part
  const auto [gated_m, gated_inliers] = error(3.0);
  EXPECT_LT(gated_m, 1e-5);
  EXPECT_LE(gated_inliers, walls);
}

// Under Gaussian range noise the gate keeps nearly every pair (a 3-sigma cut drops 0.3 %; the
// MAD scale and corner fits allow a little more), where a 10 % trim drops a tenth of them.
TEST(Icp, RobustGateKeepsGaussianResiduals) {
  const Case c = cases()[1];
  const Points2 ref = staticScan(c.T_world_ref, 0.01, 7), cur = staticScan(c.T_world_cur, 0.01, 8);
  IcpParams gated;
  gated.trim_fraction = 0.0;
  gated.outlier_sigmas = 3.0;
  const IcpResult r = matchPointToLine(ref, cur, SE2(), gated);
  ASSERT_TRUE(r.converged) << r.reason;
  IcpParams ungated = gated;
  ungated.outlier_sigmas = 0.0;
  const IcpResult all = matchPointToLine(ref, cur, SE2(), ungated);
  ASSERT_TRUE(all.converged) << all.reason;
  EXPECT_GE(static_cast<double>(r.inliers), 0.97 * static_cast<double>(all.inliers));
  EXPECT_LT(r.inliers, all.inliers);  // ... but not none: corners and the tails go
}

TEST(Icp, RefusesWithoutOverlap) {
  const Points2 ref = staticScan(SE2());
  const IcpResult r = matchPointToLine(ref, ref, SE2(50.0, 0.0, 0.0), {});
  EXPECT_FALSE(r.converged);
  EXPECT_NE(r.reason.find("correspondences"), std::string::npos);
  EXPECT_TRUE(r.covariance.allFinite());
}

}  // namespace
}  // namespace slamprep::algo
