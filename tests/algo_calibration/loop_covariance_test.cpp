#include "slamprep/algo/calibration/loop_covariance.hpp"

#include <gtest/gtest.h>

#include <random>

#include "slamprep/algo/matching/loop_closure.hpp"

namespace slamprep::algo {
namespace {

// Twelve intervals of 0.1 s laid end to end: boundary k at t = 0.1 k.
std::vector<CalibrationInterval> intervals12() {
  std::vector<CalibrationInterval> out(12);
  for (std::size_t k = 0; k < out.size(); ++k) {
    out[k].t_start_s = 0.1 * k;
    out[k].t_end_s = 0.1 * (k + 1);
  }
  return out;
}

// Two overlapping loops, boundaries 0 -> 8 and 3 -> 12 (the end of the last interval).
const std::vector<LoopSpan> kLoops = {{0.0, 0.8}, {0.3, 1.2}};
const std::vector<std::pair<std::size_t, std::size_t>> kBoundaries = {{0, 8}, {3, 12}};

// The correction headingCorrections() applies to intervals whose heading errors are e when the
// direct matches err by eps: each loop reads c = eps - (sum of e over its intervals). Returns
// the change of every interval's heading.
Eigen::VectorXd changeOf(const Eigen::VectorXd& e, const Eigen::VectorXd& eps) {
  std::vector<LoopClosure> loops;
  for (std::size_t l = 0; l < kBoundaries.size(); ++l) {
    const auto [from, to] = kBoundaries[l];
    const double sum =
        e.segment(static_cast<Eigen::Index>(from), static_cast<Eigen::Index>(to - from)).sum();
    loops.push_back({from, to, eps(static_cast<Eigen::Index>(l)) - sum});
  }
  const std::vector<double> delta =
      headingCorrections(static_cast<std::size_t>(e.size()) + 1, loops);
  Eigen::VectorXd change(e.size());
  for (Eigen::Index k = 0; k < e.size(); ++k) change(k) = delta[k + 1] - delta[k];
  return change;
}

// Brute force: K and K_eps column by column from the correction itself, then Y = (I - K)^T J and
// Z = K_eps^T J against loopCorrectedRows().
TEST(LoopCovariance, RowsMatchTheCorrectionAppliedColumnByColumn) {
  const auto intervals = intervals12();
  const Eigen::Index n = 12, loops = 2;
  Eigen::MatrixXd K(n, n), K_eps(n, loops);
  for (Eigen::Index j = 0; j < n; ++j)
    K.col(j) = -changeOf(Eigen::VectorXd::Unit(n, j), Eigen::VectorXd::Zero(loops));
  for (Eigen::Index l = 0; l < loops; ++l)
    K_eps.col(l) = changeOf(Eigen::VectorXd::Zero(n), Eigen::VectorXd::Unit(loops, l));
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd J(n, 3);
  for (Eigen::Index i = 0; i < J.size(); ++i) J(i) = normal(rng);
  const LoopCorrectedRows rows = loopCorrectedRows(intervals, kLoops, J);
  const Eigen::MatrixXd I = Eigen::MatrixXd::Identity(n, n);
  EXPECT_LT((rows.Y - (I - K).transpose() * J).norm(), 1e-12);
  EXPECT_LT((rows.Z - K_eps.transpose() * J).norm(), 1e-12);
  // A heading error common to every interval inside both loops is what a loop removes: the
  // corrected errors (I - K) e of a constant e are far smaller than e.
  const Eigen::VectorXd corrected = (I - K) * Eigen::VectorXd::Ones(n);
  EXPECT_LT(corrected.cwiseAbs().maxCoeff(), 0.5);
}

TEST(LoopCovariance, WithoutLoopsItIsTheLongRunScoreCovariance) {
  const auto intervals = intervals12();
  Eigen::MatrixXd J = Eigen::MatrixXd::Random(12, 2);
  EXPECT_LT((loopScoreCovariance(intervals, {}, J, {}, 0.4) - 0.4 * J.transpose() * J).norm(),
            1e-14);
}

// Residuals that sum to s over each loop's span are the direct match's own error: nothing is
// left for the wheels, the matcher's share is 1. Sums of 2 s over 8 and 9 intervals at f = 0.5
// leave (4 - 1) / 4 and (4 - 1) / 4.5 of it to the wheels: a = 1 - (3/4 + 2/3) / 2.
TEST(LoopCovariance, MatcherShareIsWhatTheWheelsLeaveOverTheLoops) {
  const auto intervals = intervals12();
  auto spanSums = [](double first, double second) {  // residuals 0 except one per span
    std::vector<double> r(12, 0.0);
    r[0] = first;    // span 0 -> 8 only
    r[11] = second;  // span 3 -> 12 only
    return r;
  };
  EXPECT_NEAR(matcherShare(intervals, kLoops, spanSums(1.0, 1.0), 0.5), 1.0, 1e-15);
  EXPECT_NEAR(matcherShare(intervals, kLoops, spanSums(2.0, 2.0), 0.5),
              1.0 - (3.0 / 4.0 + 2.0 / 3.0) / 2.0, 1e-12);
  EXPECT_EQ(matcherShare(intervals, kLoops, spanSums(30.0, 30.0), 0.5), 0.0);  // clamped
  EXPECT_EQ(matcherShare(intervals, {}, spanSums(3.0, 3.0), 0.5), 0.0);
}

TEST(LoopCovariance, ALoopOutsideTheIntervalsChangesNothing) {
  const auto intervals = intervals12();
  const Eigen::MatrixXd J = Eigen::MatrixXd::Random(12, 2);
  const LoopCorrectedRows rows = loopCorrectedRows(intervals, {{5.0, 6.0}}, J);
  EXPECT_EQ(rows.Z.rows(), 0);
  EXPECT_LT((rows.Y - J).norm(), 1e-15);
}

}  // namespace
}  // namespace slamprep::algo
