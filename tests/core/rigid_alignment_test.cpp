// core/rigid_alignment: the closed form against a brute-force search over the angle, forward and
// inverse, and its refusals.
#include "slamprep/core/rigid_alignment.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

namespace slamprep {
namespace {

using Points = std::vector<Eigen::Vector2d>;

double cost(const SE2& T_q_p, const Points& p, const Points& q) {
  double sum = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) sum += (q[i] - T_q_p * p[i]).squaredNorm();
  return sum;
}

// For a fixed angle the best translation is mean(q) - R mean(p): search the angle on a grid of
// 1e-3 rad, then on one of 1e-6 rad around the best.
SE2 bruteForce(const Points& p, const Points& q) {
  Eigen::Vector2d p_mean = Eigen::Vector2d::Zero(), q_mean = Eigen::Vector2d::Zero();
  for (std::size_t i = 0; i < p.size(); ++i) p_mean += p[i] / double(p.size());
  for (std::size_t i = 0; i < q.size(); ++i) q_mean += q[i] / double(q.size());
  SE2 best;
  double best_cost = INFINITY;
  const auto search = [&](double from, double step, int steps) {
    const double centre = best.yaw;
    for (int k = 0; k <= steps; ++k) {
      const double theta = centre + from + k * step;
      const Eigen::Vector2d t = q_mean - SE2(0, 0, theta).rotation() * p_mean;
      const SE2 T(t.x(), t.y(), theta);
      if (const double c = cost(T, p, q); c < best_cost) best_cost = c, best = T;
    }
  };
  search(-std::numbers::pi, 1e-3, 6284);
  search(-2e-3, 1e-6, 4000);
  return best;
}

TEST(RigidAlignment, ClosedFormIsTheMinimumABruteForceSearchFinds) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coord(-5.0, 5.0);
  std::normal_distribution<double> noise(0.0, 0.05);
  const SE2 T_q_p(1.5, -2.0, 2.5);  // beyond +-pi/2: no small-angle shortcut works
  Points p(40), q(40);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p[i] = {coord(rng), coord(rng)};
    q[i] = T_q_p * p[i] + Eigen::Vector2d(noise(rng), noise(rng));
  }
  const RigidAlignment2D solved = solveRigid2D(p, q);
  ASSERT_TRUE(solved.T_q_p) << solved.reason;
  const SE2 brute = bruteForce(p, q);
  EXPECT_LE(cost(*solved.T_q_p, p, q), cost(brute, p, q) + 1e-12);  // no angle does better
  EXPECT_NEAR(solved.T_q_p->yaw, brute.yaw, 2e-6);
  EXPECT_NEAR(solved.T_q_p->yaw, T_q_p.yaw, 0.01);  // and the noise moves it little
}

TEST(RigidAlignment, ForwardAndInverseOfAnExactMotion) {
  const Points p = {{0, 0}, {2, 0}, {2, 1}, {-1, 3}};
  const SE2 T_q_p(-0.3, 0.7, -3.0);
  Points q;
  for (const auto& x : p) q.push_back(T_q_p * x);
  const RigidAlignment2D forward = solveRigid2D(p, q), inverse = solveRigid2D(q, p);
  ASSERT_TRUE(forward.T_q_p && inverse.T_q_p);
  EXPECT_NEAR(forward.T_q_p->x, T_q_p.x, 1e-12);
  EXPECT_NEAR(forward.T_q_p->y, T_q_p.y, 1e-12);
  EXPECT_NEAR(forward.T_q_p->yaw, T_q_p.yaw, 1e-12);
  const SE2 identity = *forward.T_q_p * *inverse.T_q_p;
  EXPECT_NEAR(identity.x, 0.0, 1e-12);
  EXPECT_NEAR(identity.y, 0.0, 1e-12);
  EXPECT_NEAR(identity.yaw, 0.0, 1e-12);
}

TEST(RigidAlignment, RefusesWhatDoesNotFixARotation) {
  EXPECT_FALSE(solveRigid2D(Points{{1, 1}}, Points{{2, 2}}).T_q_p);
  EXPECT_FALSE(solveRigid2D(Points{{1, 1}, {1, 1}}, Points{{0, 0}, {3, 3}}).T_q_p);
  const RigidAlignment2D nan = solveRigid2D(Points{{0, 0}, {NAN, 1}}, Points{{0, 0}, {1, 1}});
  EXPECT_FALSE(nan.T_q_p);
  EXPECT_NE(nan.reason.find("rotation unobservable"), std::string::npos);
}

}  // namespace
}  // namespace slamprep
