#include "slamprep/core/se2.hpp"

#include <ceres/jet.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>
#include <random>

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

// The in-range shortcut must give exactly what std::remainder gives (results are compared bit for
// bit across versions): both sides of +-pi, zero, and random angles over several turns.
TEST(NormalizeAngle, EqualsRemainderBitForBit) {
  auto byRemainder = [](double a) {
    const double r = std::remainder(a, 2.0 * kPi);
    return r <= -kPi ? r + 2.0 * kPi : r;
  };
  std::vector<double> angles = {0.0,
                                -0.0,
                                kPi,
                                -kPi,
                                std::nextafter(kPi, 4.0),
                                std::nextafter(kPi, 0.0),
                                std::nextafter(-kPi, -4.0),
                                std::nextafter(-kPi, 0.0),
                                2 * kPi,
                                -2 * kPi,
                                1e-300};
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> turns(-20.0, 20.0);
  for (int i = 0; i < 100000; ++i) angles.push_back(turns(rng));
  for (double a : angles) EXPECT_EQ(normalizeAngle(a), byRemainder(a)) << a;
}

TEST(SE2, ComposeMatchesMatrixProduct) {
  const SE2 a(1.0, -2.0, 0.7), b(-0.3, 0.5, -2.9);
  expectPoseNear(a * b, SE2::fromMatrix(a.matrix() * b.matrix()), 1e-12);
  // Yaws summing past pi wrap, and the matrices agree.
  const SE2 c(0.2, 0.1, 3.0), d(-1.0, 2.0, 2.5);
  expectPoseNear(c * d, SE2::fromMatrix(c.matrix() * d.matrix()), 1e-12);
  EXPECT_LE((c * d).yaw, kPi);
  EXPECT_GT((c * d).yaw, -kPi);
}

TEST(SE2, InverseComposesToIdentity) {
  const SE2 a(3.0, 4.0, 2.5);
  expectPoseNear(a * a.inverse(), SE2(), 1e-12);
  expectPoseNear(a.inverse() * a, SE2(), 1e-12);
  EXPECT_NEAR((a.inverse().matrix() - a.matrix().inverse()).norm(), 0.0, 1e-12);
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

// Round trips across both branches of sinc/cosc: zero, tiny, just either side of the series
// cut-off, ordinary, and within 1e-9 of +-pi. log(exp(xi)) = xi needs |theta| < pi.
TEST(SE2, ExpLogRoundTrip) {
  const double cut = kSmallAngleRad;
  for (double theta : {0.0, 1e-12, -1e-7, 0.99 * cut, -1.01 * cut, 3e-4, 1.0, 3.0, -3.0, kPi - 1e-9,
                       -kPi + 1e-9}) {
    for (const Eigen::Vector2d& rho : {Eigen::Vector2d(1.0, 0.2), Eigen::Vector2d(-2.0, 1.0)}) {
      const Eigen::Vector3d xi(rho.x(), rho.y(), theta);
      EXPECT_NEAR((SE2::exp(xi).log() - xi).norm(), 0.0, 1e-12) << xi.transpose();
    }
  }
  // exp(log(T)) = T, yaw = pi included (log returns theta = pi).
  for (double yaw : {0.0, 5e-5, -2e-4, 2.0, kPi, -kPi + 1e-9}) {
    const SE2 T(0.7, -0.4, yaw);
    expectPoseNear(SE2::exp(T.log()), T, 1e-12);
  }
}

// sinc and cosc are continuous across the series cut-off: the dropped terms (t^4/120 and t^5/720
// relative) and the closed forms' cancellation (~eps/t in cosc) are both below 1e-12 there.
TEST(SE2, SincCoscContinuousAtTheCutOff) {
  const double below = std::nextafter(kSmallAngleRad, 0.0);
  EXPECT_NEAR(sinc(below), sinc(kSmallAngleRad), 1e-15);
  EXPECT_NEAR(cosc(below), cosc(kSmallAngleRad), 1e-12);
  EXPECT_DOUBLE_EQ(sinc(0.0), 1.0);
  EXPECT_DOUBLE_EQ(cosc(0.0), 0.0);
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

TEST(SE2, CastCarriesTheValuesExactly) {
  const SE2 T(0.1, -0.2, kPi);
  const SE2T<float> f = T.cast<float>();
  EXPECT_EQ(f.x, 0.1f);
  EXPECT_EQ(f.yaw, static_cast<float>(kPi));
  const SE2 back = f.cast<double>();
  EXPECT_EQ(back.y, static_cast<double>(-0.2f));
}

using Jet3 = ceres::Jet<double, 3>;

// r(xi) = log(T_a_b^-1 * T_a * exp(xi) * T_c): a pose-graph style residual through every
// operation a cost functor uses.
template <typename Scalar>
Eigen::Matrix<Scalar, 3, 1> residual(const Eigen::Matrix<Scalar, 3, 1>& xi) {
  const SE2T<Scalar> T_a = SE2(0.3, -0.2, 0.4).cast<Scalar>();
  const SE2T<Scalar> T_c = SE2(1.0, 0.5, -2.0).cast<Scalar>();
  const SE2T<Scalar> T_a_b = SE2(0.9, 0.1, 1.7).cast<Scalar>();
  return between(T_a_b, T_a * SE2T<Scalar>::exp(xi) * T_c).log();
}

// The Jet instantiation's derivative against central differences (h = 1e-6): truncation
// ~h^2 |r'''| ~ 1e-12, rounding ~eps |r| / h ~ 1e-9; asserted 1e-8.
TEST(SE2Jet, DerivativeMatchesFiniteDifference) {
  for (const Eigen::Vector3d& xi0 :
       {Eigen::Vector3d(0.2, -0.1, 0.3), Eigen::Vector3d(-1.0, 0.4, 2.0),
        Eigen::Vector3d(0.5, 0.5, -1.2)}) {
    Eigen::Matrix<Jet3, 3, 1> xi;
    for (int i = 0; i < 3; ++i) xi(i) = Jet3(xi0(i), i);
    const Eigen::Matrix<Jet3, 3, 1> r = residual(xi);
    const double h = 1e-6;
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(j);
      const Eigen::Vector3d fd =
          (residual<double>(xi0 + step) - residual<double>(xi0 - step)) / (2 * h);
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(r(i).a, residual<double>(xi0)(i), 1e-15);
        EXPECT_NEAR(r(i).v(j), fd(i), 1e-8)
            << "d r" << i << " / d xi" << j << " at " << xi0.transpose();
      }
    }
  }
}

// Below the cut-off the Jets differentiate the series; its derivatives -t/3 and 1/2 - t^2/8
// differ from the exact ones by t^3/30 and t^4/144, far below 1e-15 at t = 1e-5.
TEST(SE2Jet, SmallAngleDerivativesOfSincCosc) {
  const double t = 1e-5;
  const Jet3 s = sinc(Jet3(t, 0)), c = cosc(Jet3(t, 0));
  EXPECT_NEAR(s.v(0), -t / 3.0, 1e-15);
  EXPECT_NEAR(c.v(0), 0.5 - t * t / 8.0, 1e-15);
}

// For a Jet normalizeAngle passes (-pi, pi] through and wraps outside by atan2(sin, cos); the
// derivative is 1 either way.
TEST(SE2Jet, NormalizeAngleWrapsWithUnitDerivative) {
  const Jet3 wrapped = normalizeAngle(Jet3(3 * kPi + 0.1, 2));
  EXPECT_NEAR(wrapped.a, -kPi + 0.1, 1e-12);
  EXPECT_EQ(wrapped.v(2), 1.0);
  const Jet3 inside = normalizeAngle(Jet3(-3.0, 2));
  EXPECT_EQ(inside.a, -3.0);
  EXPECT_EQ(inside.v(2), 1.0);
  EXPECT_EQ(normalizeAngle(Jet3(-kPi, 0)).a, kPi);
}

}  // namespace
}  // namespace slamprep
