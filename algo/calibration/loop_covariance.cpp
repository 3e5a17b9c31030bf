#include "slamprep/algo/calibration/loop_covariance.hpp"

#include <Eigen/Sparse>
#include <algorithm>
#include <utility>

#include "slamprep/algo/matching/loop_closure.hpp"

namespace slamprep::algo {
namespace {

// The boundary (interval index; intervals.size() = the end of the last) at or after t.
std::size_t boundaryAt(const std::vector<CalibrationInterval>& intervals, double t_s) {
  const auto it = std::lower_bound(
      intervals.begin(), intervals.end(), t_s - 1e-9,
      [](const CalibrationInterval& interval, double t) { return interval.t_start_s < t; });
  return static_cast<std::size_t>(it - intervals.begin());
}

// Each loop as the interval boundaries it spans, from < to; loops spanning no interval dropped.
std::vector<std::pair<std::size_t, std::size_t>> loopBoundaries(
    const std::vector<CalibrationInterval>& intervals, const std::vector<LoopSpan>& loops) {
  std::vector<std::pair<std::size_t, std::size_t>> spans;
  for (const LoopSpan& loop : loops) {
    const std::size_t from = boundaryAt(intervals, loop.t_from_s);
    const std::size_t to = boundaryAt(intervals, loop.t_to_s);
    if (from < to) spans.emplace_back(from, to);
  }
  return spans;
}

}  // namespace

LoopCorrectedRows loopCorrectedRows(const std::vector<CalibrationInterval>& intervals,
                                    const std::vector<LoopSpan>& loops, const Eigen::MatrixXd& J) {
  const std::size_t n = intervals.size();
  const auto spans = loopBoundaries(intervals, loops);
  LoopCorrectedRows out{J,
                        Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(spans.size()), J.cols())};
  if (spans.empty()) return out;
  // D^T J over the unknown boundaries 1..n: interval k's change is delta_{k+1} - delta_k.
  const auto unknowns = static_cast<Eigen::Index>(n);
  Eigen::MatrixXd DtJ = Eigen::MatrixXd::Zero(unknowns, J.cols());
  for (Eigen::Index k = 0; k < unknowns; ++k) {
    DtJ.row(k) += J.row(k);                 // + delta_{k+1}: unknown k
    if (k > 0) DtJ.row(k - 1) -= J.row(k);  // - delta_k: unknown k - 1
  }
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(headingGraphMatrix(n + 1, spans));
  const Eigen::MatrixXd X = solver.solve(DtJ);  // H^-1 D^T J
  for (std::size_t l = 0; l < spans.size(); ++l) {
    const auto [from, to] = spans[l];
    Eigen::RowVectorXd w = X.row(static_cast<Eigen::Index>(to) - 1);  // A^T X
    if (from > 0) w -= X.row(static_cast<Eigen::Index>(from) - 1);
    out.Z.row(static_cast<Eigen::Index>(l)) = w;
    for (std::size_t k = from; k < to; ++k) out.Y.row(static_cast<Eigen::Index>(k)) -= w;  // L^T
  }
  return out;
}

double matcherShare(const std::vector<CalibrationInterval>& intervals,
                    const std::vector<LoopSpan>& loops, const std::vector<double>& residuals,
                    double f) {
  double wheel = 0.0;  // mean over loops of the wheels' share
  const auto spans = loopBoundaries(intervals, loops);
  if (spans.empty() || !(f > 0.0)) return 0.0;
  for (const auto& [from, to] : spans) {
    double sum = 0.0;
    for (std::size_t k = from; k < to; ++k) sum += residuals[k];
    wheel += (sum * sum - 1.0) / (static_cast<double>(to - from) * f);
  }
  return std::clamp(1.0 - wheel / static_cast<double>(spans.size()), 0.0, 1.0);
}

Eigen::MatrixXd loopScoreCovariance(const std::vector<CalibrationInterval>& intervals,
                                    const std::vector<LoopSpan>& loops, const Eigen::MatrixXd& J,
                                    const std::vector<double>& residuals, double f) {
  const double a = matcherShare(intervals, loops, residuals, f);
  const LoopCorrectedRows rows = loopCorrectedRows(intervals, loops, J);
  return f * ((1.0 - a) * J.transpose() * J + a * rows.Y.transpose() * rows.Y) +
         rows.Z.transpose() * rows.Z;
}

}  // namespace slamprep::algo
