#include "core/se2.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

namespace slamprep {
namespace {

constexpr double kPi = std::numbers::pi;

void expectPoseNear(const SE2& a, const SE2& b, double tol) {
  EXPECT_NEAR(a.x, b.x, tol);
  EXPECT_NEAR(a.y, b.y, tol);
  EXPECT_NEAR(normalizeAngle(a.yaw - b.yaw), 0.0, tol);
}

TEST(NormalizeAngle, MapsIntoHalfOpenInterval) {
  EXPECT_DOUBLE_EQ(normalizeAngle(kPi), kPi);
  EXPECT_DOUBLE_EQ(normalizeAngle(-kPi), kPi);
  EXPECT_NEAR(normalizeAngle(3 * kPi + 0.1), -kPi + 0.1, 1e-12);
  EXPECT_NEAR(normalizeAngle(-7.0), -7.0 + 2 * kPi, 1e-12);
}

TEST(SE2, ComposeMatchesMatrixProduct) {
  const SE2 a(1.0, -2.0, 0.7), b(-0.3, 0.5, -2.9);
  expectPoseNear(a * b, SE2::fromMatrix(a.matrix() * b.matrix()), 1e-12);
}

TEST(SE2, InverseComposesToIdentity) {
  const SE2 a(3.0, 4.0, 2.5);
  expectPoseNear(a * a.inverse(), SE2(), 1e-12);
  expectPoseNear(a.inverse() * a, SE2(), 1e-12);
}

TEST(SE2, BetweenIsRelativePose) {
  const SE2 T_w_a(1.0, 2.0, 0.3), T_w_b(-1.0, 0.5, -1.2);
  expectPoseNear(T_w_a * between(T_w_a, T_w_b), T_w_b, 1e-12);
}

TEST(SE2, TransformsPointsLikeTheMatrix) {
  const SE2 T(0.5, -1.0, 1.1);
  const Eigen::Vector2d p(2.0, 3.0);
  const Eigen::Vector3d q = T.matrix() * Eigen::Vector3d(p.x(), p.y(), 1.0);
  EXPECT_NEAR((T * p - q.head<2>()).norm(), 0.0, 1e-12);
}

TEST(SE2, ExpLogRoundTrip) {
  for (const Eigen::Vector3d& xi :
       {Eigen::Vector3d(1.0, 0.2, 0.0), Eigen::Vector3d(0.4, -0.3, 1e-7),
        Eigen::Vector3d(-2.0, 1.0, 3.0)}) {
    EXPECT_NEAR((SE2::exp(xi).log() - xi).norm(), 0.0, 1e-12) << xi.transpose();
  }
}

TEST(SE2, ExpOfPureRotationAndArc) {
  // A unit-speed arc of angle th and radius 1 ends at (sin th, 1 - cos th).
  const double th = 0.9;
  expectPoseNear(SE2::exp({th, 0.0, th}), SE2(std::sin(th), 1 - std::cos(th), th), 1e-12);
}

TEST(SE2, InterpolateHitsEndsAndFollowsTheArc) {
  const SE2 a(1.0, 1.0, 0.2);
  const SE2 b = a * SE2::exp({2.0, 0.0, 1.0});
  expectPoseNear(interpolate(a, b, 0.0), a, 1e-12);
  expectPoseNear(interpolate(a, b, 1.0), b, 1e-12);
  expectPoseNear(interpolate(a, b, 0.25), a * SE2::exp({0.5, 0.0, 0.25}), 1e-12);
}

}  // namespace
}  // namespace slamprep
