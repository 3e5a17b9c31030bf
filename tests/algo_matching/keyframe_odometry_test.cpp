// Scan-to-local-map odometry (algo/matching/keyframe_odometry.hpp): the local map's frames, when
// keyframes start, how many the map holds, and the failed-match policy (the odometry step,
// counted), on noiseless scans of the synthetic room.
#include "slamprep/algo/matching/keyframe_odometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "slamprep/tests/algo_deskew/synthetic_world.hpp"

namespace slamprep::algo {
namespace {

using slamprep::testing::roomWorld;
using slamprep::testing::standingScan;

/// A 360-beam scan over a full turn from one pose (no motion during the scan), noiseless.
Points2 scanAt(const SE2& T_world_lidar) {
  return standingScan(roomWorld(), T_world_lidar, 360);
}

/// n poses from (-1.5, -0.5, 0), each `step` after the last.
std::vector<SE2> path(std::size_t n, const SE2& step) {
  std::vector<SE2> poses{SE2(-1.5, -0.5, 0.0)};
  while (poses.size() < n) poses.push_back(poses.back() * step);
  return poses;
}

struct Log {
  std::vector<Points2> points;
  std::vector<std::optional<SE2>> increments;  // true steps unless changed by the test
};

Log logAlong(const std::vector<SE2>& truth) {
  Log log;
  for (std::size_t k = 0; k < truth.size(); ++k) {
    log.points.push_back(scanAt(truth[k]));
    log.increments.push_back(k == 0 ? std::nullopt
                                    : std::optional<SE2>(between(truth[k - 1], truth[k])));
  }
  return log;
}

// Noiseless polygon scans: point-to-line's fixed point is the truth up to the default step
// tolerance (0.1 mm, 1e-5 rad); 1 mm / 1 mrad leaves room for the few corner fits trimming keeps.
constexpr double kPoseTolM = 1e-3, kYawTolRad = 1e-3;

// 0.1 m per scan, keyframe beyond 0.35 m: scans 4, 8, 12, 16 start keyframes (0.4 m from the
// last), with scan 0 five in all; only keyframes add points to the map.
TEST(KeyframeOdometry, NewKeyframeAfterTheDistanceAndOnlyKeyframesGrowTheMap) {
  const std::vector<SE2> truth = path(20, SE2(0.1, 0.0, 0.0));
  const Log log = logAlong(truth);
  KeyframeOdometryParams params;
  params.keyframe_distance_m = 0.35;
  const KeyframeOdometry run = trackKeyframes(log.points, log.increments, params, truth[0]);
  ASSERT_EQ(run.scans.size(), truth.size());
  EXPECT_EQ(run.matched, 19u);
  EXPECT_EQ(run.fallbacks, 0u);
  EXPECT_EQ(run.keyframes, 5u);
  for (std::size_t k = 0; k < truth.size(); ++k) {
    SCOPED_TRACE(k);
    EXPECT_EQ(run.scans[k].is_keyframe, k % 4 == 0);
    EXPECT_EQ(run.scans[k].keyframe, k == 0 ? 0 : (k - 1) / 4 * 4);  // the keyframe before it
    EXPECT_NEAR(run.scans[k].T_world_lidar.x, truth[k].x, kPoseTolM);
    EXPECT_NEAR(run.scans[k].T_world_lidar.y, truth[k].y, kPoseTolM);
    EXPECT_NEAR(run.scans[k].T_world_lidar.yaw, truth[k].yaw, kYawTolRad);
  }
  // Between keyframes the map stays as it is; a keyframe 0.4 m on adds the walls it newly sees,
  // but far fewer points than its scan has (the rest lie within 5 cm of the map's).
  for (std::size_t k = 1; k < truth.size(); ++k)
    if (k % 4 != 1) {
      EXPECT_EQ(run.scans[k].map_points, run.scans[k - 1].map_points) << k;
    }
  EXPECT_GT(run.scans[5].map_points, run.scans[4].map_points);
  EXPECT_LT(run.scans[5].map_points - run.scans[4].map_points, log.points[4].size() / 2);
}

// Turning on the spot by 0.05 rad per scan, keyframe beyond 10 degrees (0.1745 rad): every 4th
// scan (0.2 rad) starts one.
TEST(KeyframeOdometry, NewKeyframeAfterTheAngle) {
  const std::vector<SE2> truth = path(13, SE2(0.0, 0.0, 0.05));
  const Log log = logAlong(truth);
  const KeyframeOdometry run = trackKeyframes(log.points, log.increments, {}, truth[0]);
  EXPECT_EQ(run.keyframes, 4u);
  EXPECT_TRUE(run.scans[4].is_keyframe && run.scans[8].is_keyframe && run.scans[12].is_keyframe);
  EXPECT_NEAR(run.scans.back().T_world_lidar.yaw, truth.back().yaw, kYawTolRad);
}

// The guess is the odometry step: a 5 cm / 2 degree error in every step is corrected by the match,
// so the end pose is the truth, not the odometry's 0.5 m away.
TEST(KeyframeOdometry, TheMatchCorrectsABiasedOdometryGuess) {
  const std::vector<SE2> truth = path(11, SE2(0.1, 0.0, 0.02));
  Log log = logAlong(truth);
  for (std::size_t k = 1; k < log.increments.size(); ++k)
    log.increments[k] = *log.increments[k] * SE2(0.05, 0.0, 0.035);
  const KeyframeOdometry run = trackKeyframes(log.points, log.increments, {}, truth[0]);
  EXPECT_EQ(run.matched, 10u);
  EXPECT_NEAR(run.scans.back().T_world_lidar.x, truth.back().x, kPoseTolM);
  EXPECT_NEAR(run.scans.back().T_world_lidar.y, truth.back().y, kPoseTolM);
  EXPECT_NEAR(run.scans.back().T_world_lidar.yaw, truth.back().yaw, kYawTolRad);
}

// Policy: a scan that cannot be matched (here: no points) is placed by the previous pose o its
// odometry step, exactly, and counted; the next scans match again.
TEST(KeyframeOdometry, AFailedMatchFallsBackToTheOdometryStepAndIsCounted) {
  const std::vector<SE2> truth = path(8, SE2(0.1, 0.02, 0.01));
  Log log = logAlong(truth);
  log.points[3].clear();
  const SE2 odometry_step(0.12, 0.0, 0.0);  // 2 cm and 0.01 rad off the truth
  log.increments[3] = odometry_step;
  const KeyframeOdometry run = trackKeyframes(log.points, log.increments, {}, truth[0]);
  EXPECT_EQ(run.matched, 6u);
  EXPECT_EQ(run.fallbacks, 1u);
  EXPECT_EQ(run.rejected, 0u);
  EXPECT_EQ(run.sparse, 1u);  // an empty scan: no guess could have matched it
  EXPECT_EQ(run.scans[3].points, 0u);
  EXPECT_TRUE(run.scans[3].fallback);
  EXPECT_FALSE(run.scans[3].match.converged);
  EXPECT_FALSE(run.scans[3].match.reason.empty());
  const SE2 expected = run.scans[2].T_world_lidar * odometry_step;
  EXPECT_EQ(run.scans[3].T_world_lidar.x, expected.x);
  EXPECT_EQ(run.scans[3].T_world_lidar.y, expected.y);
  EXPECT_EQ(run.scans[3].T_world_lidar.yaw, expected.yaw);
  // Scan 4 is matched against the map again: back on the truth.
  EXPECT_FALSE(run.scans[4].fallback);
  EXPECT_NEAR(run.scans[4].T_world_lidar.x, truth[4].x, kPoseTolM);
  EXPECT_NEAR(run.scans[4].T_world_lidar.yaw, truth[4].yaw, kYawTolRad);
}

// A scan with fewer points than ICP's min_inliers is counted as sparse, one with as many is not:
// every 18th beam of 360 leaves 20, every 19th 19.
TEST(KeyframeOdometry, AScanWithFewerPointsThanICPNeedsIsCountedAsSparse) {
  const std::vector<SE2> truth = path(4, SE2(0.1, 0.0, 0.0));
  Log log = logAlong(truth);
  const auto everyNth = [](const Points2& p, std::size_t n) {
    Points2 out;
    for (std::size_t i = 0; i < p.size(); i += n) out.push_back(p[i]);
    return out;
  };
  log.points[2] = everyNth(log.points[2], 19);
  log.points[3] = everyNth(log.points[3], 18);
  const KeyframeOdometry run = trackKeyframes(log.points, log.increments, {}, truth[0]);
  ASSERT_EQ(run.scans[2].points, 19u);
  ASSERT_EQ(run.scans[3].points, 20u);
  EXPECT_EQ(run.sparse, 1u);
  EXPECT_TRUE(run.scans[2].fallback);
  EXPECT_NE(run.scans[2].match.reason.find("only 19 points"), std::string::npos);
  EXPECT_EQ(run.scans[1].points, 360u);
}

// Policy: a match that converges farther from the guess than max_correction is not believed.
// Guess 5 cm off, limit 2 cm: the match finds the truth 5 cm away and is rejected.
TEST(KeyframeOdometry, AMatchBeyondTheCorrectionLimitIsRejectedAndCounted) {
  const std::vector<SE2> truth = path(3, SE2(0.1, 0.0, 0.0));
  Log log = logAlong(truth);
  log.increments[2] = SE2(0.15, 0.0, 0.0);
  KeyframeOdometryParams params;
  params.max_correction_m = 0.02;
  const KeyframeOdometry run = trackKeyframes(log.points, log.increments, params, truth[0]);
  EXPECT_EQ(run.matched, 1u);
  EXPECT_EQ(run.fallbacks, 1u);
  EXPECT_EQ(run.rejected, 1u);
  EXPECT_EQ(run.sparse, 0u);
  EXPECT_TRUE(run.scans[2].match.converged);
  EXPECT_TRUE(run.scans[2].fallback);
  const SE2 expected = run.scans[1].T_world_lidar * SE2(0.15, 0.0, 0.0);
  EXPECT_NEAR(run.scans[2].T_world_lidar.x, expected.x, 1e-12);
}

// Without odometry the guess repeats the last accepted step (constant velocity per scan).
TEST(KeyframeOdometry, WithoutOdometryTheLastStepIsTheGuess) {
  const std::vector<SE2> truth = path(10, SE2(0.08, 0.01, 0.03));
  Log log = logAlong(truth);
  for (auto& inc : log.increments) inc.reset();
  const KeyframeOdometry run = trackKeyframes(log.points, log.increments, {}, truth[0]);
  EXPECT_EQ(run.matched, 9u);
  EXPECT_NEAR(run.scans.back().T_world_lidar.x, truth.back().x, kPoseTolM);
  EXPECT_NEAR(run.scans.back().T_world_lidar.y, truth.back().y, kPoseTolM);
  EXPECT_NEAR(run.scans.back().T_world_lidar.yaw, truth.back().yaw, kYawTolRad);
}

// A stale odometry that catches up (seen on a benchmark log: one value held for five scans while
// the robot turned, then an 85 degree jump): the scans follow the turn meanwhile, so adding the
// catch-up to the tracked pose would double it. Matched from every guess, the constant-velocity
// one explains the scan; the result is the truth and no scan falls back.
TEST(KeyframeOdometry, AStaleOdometryThatCatchesUpIsNotFollowed) {
  const std::vector<SE2> truth = path(16, SE2(0.05, 0.0, 0.26));  // 15 degrees per scan
  Log log = logAlong(truth);
  for (std::size_t k = 5; k <= 10; ++k) log.increments[k] = SE2();  // held ...
  log.increments[11] = between(truth[4], truth[11]);                // ... then caught up
  const KeyframeOdometry run = trackKeyframes(log.points, log.increments, {}, truth[0]);
  EXPECT_EQ(run.fallbacks, 0u);
  EXPECT_EQ(run.scans[11].guess, GuessSource::kConstantVelocity);
  for (std::size_t k = 0; k < truth.size(); ++k) {
    SCOPED_TRACE(k);
    EXPECT_NEAR(run.scans[k].T_world_lidar.x, truth[k].x, kPoseTolM);
    EXPECT_NEAR(run.scans[k].T_world_lidar.y, truth[k].y, kPoseTolM);
    EXPECT_NEAR(normalizeAngle(run.scans[k].T_world_lidar.yaw - truth[k].yaw), 0.0, kYawTolRad);
  }
  // The same log matched from the odometry guess alone ends far off: what the test guards.
  KeyframeOdometryParams odometry_only;
  odometry_only.hypothesis_separation_m = 1e9;
  odometry_only.hypothesis_separation_rad = 1e9;
  const KeyframeOdometry alone =
      trackKeyframes(log.points, log.increments, odometry_only, truth[0]);
  EXPECT_GT(std::abs(normalizeAngle(alone.scans.back().T_world_lidar.yaw - truth.back().yaw)), 0.5);
}

// The gyro's turn is a guess of its own: with the odometry's yaw 30 degrees off in one step and
// the gyro right, the gyro's guess wins.
TEST(KeyframeOdometry, TheGyroGuessWinsWhereTheOdometryTurnIsWrong) {
  const std::vector<SE2> truth = path(8, SE2(0.12, 0.0, 0.05));  // 0.12 m: "still" is a guess too
  const Log log = logAlong(truth);
  std::vector<StepPrior> priors(truth.size());
  for (std::size_t k = 1; k < truth.size(); ++k) {
    priors[k].odometry = log.increments[k];
    priors[k].gyro_yaw_rad = log.increments[k]->yaw;
  }
  priors[4].odometry = *priors[4].odometry * SE2(0.0, 0.0, 0.52);
  const KeyframeOdometry run = trackKeyframes(log.points, priors, {}, truth[0]);
  EXPECT_EQ(run.fallbacks, 0u);
  EXPECT_EQ(run.scans[4].guess, GuessSource::kGyro);
  EXPECT_EQ(run.scans[4].hypotheses, 3u);  // odometry, gyro, still (constant velocity = gyro)
  EXPECT_EQ(run.multi_hypothesis, 7u);     // every scan: the odometry (= gyro) and still
  EXPECT_NEAR(run.scans.back().T_world_lidar.yaw, truth.back().yaw, kYawTolRad);
}

// Accepted because the map supports the scan: with a support threshold no scan can reach, every
// converged match falls back to a guess and is counted as unsupported.
TEST(KeyframeOdometry, AMatchTheMapDoesNotSupportIsNotAccepted) {
  const std::vector<SE2> truth = path(4, SE2(0.1, 0.0, 0.0));
  const Log log = logAlong(truth);
  KeyframeOdometryParams params;
  params.min_support_fraction = 1.01;
  const KeyframeOdometry run = trackKeyframes(log.points, log.increments, params, truth[0]);
  EXPECT_EQ(run.matched, 0u);
  EXPECT_EQ(run.fallbacks, 3u);
  EXPECT_EQ(run.unsupported, 3u);
  EXPECT_NE(run.scans[1].match.reason.find("not supported"), std::string::npos);
  EXPECT_GT(run.scans[1].support.fraction(), 0.99);  // noiseless: every point on the map
}

// The fusion of a match with the odometry guess (fuseWithGuess): a corridor along x leaves x to
// the odometry and y, yaw to the match; equal confidence gives the midpoint; sigma 0 turns it off.
TEST(KeyframeOdometry, FusionLeavesTheDirectionsTheScanDoesNotSeeToTheOdometry) {
  const SE2 match(0.30, 0.05, 0.10), guess(0.20, 0.02, 0.08);
  const Eigen::Matrix3d corridor = Eigen::Vector3d(1e6, 1e-8, 1e-10).asDiagonal();
  const SE2 fused = fuseWithGuess(match, corridor, guess, 0.01, 0.01);
  EXPECT_NEAR(fused.x, guess.x, 1e-9);  // weight 1e-4 / (1e-4 + 1e6) on the match
  EXPECT_NEAR(fused.y, match.y, 1e-5);  // weight 1e-4 / (1e-4 + 1e-8) on the match
  EXPECT_NEAR(fused.yaw, match.yaw, 1e-7);
  const Eigen::Matrix3d same = Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal();
  const SE2 mid = fuseWithGuess(match, same, guess, 0.01, 0.01);
  EXPECT_NEAR(mid.x, 0.25, 1e-12);
  EXPECT_NEAR(mid.y, 0.035, 1e-12);
  EXPECT_NEAR(mid.yaw, 0.09, 1e-12);
  const SE2 off = fuseWithGuess(match, same, guess, 0.0, 0.01);
  EXPECT_EQ(off.x, match.x);
  EXPECT_EQ(off.yaw, match.yaw);
}

}  // namespace
}  // namespace slamprep::algo
