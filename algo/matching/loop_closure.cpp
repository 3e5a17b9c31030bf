#include "slamprep/algo/matching/loop_closure.hpp"

#include <algorithm>
#include <cmath>
#include <optional>

namespace slamprep::algo {
namespace {

// Poses at least `spacing_s` apart, the first one included.
std::vector<std::size_t> keyframes(const PoseSeries& chain, double spacing_s) {
  std::vector<std::size_t> out;
  for (std::size_t i = 0; i < chain.size(); ++i)
    if (out.empty() || chain[i].stamp_s - chain[out.back()].stamp_s >= spacing_s) out.push_back(i);
  return out;
}

// The earlier keyframe nearest to keyframe `to` among those far enough back in time and close
// enough in place and heading.
std::optional<std::size_t> loopPartner(const PoseSeries& chain, const std::vector<std::size_t>& kf,
                                       std::size_t to, const LoopClosureParams& params) {
  std::optional<std::size_t> best;
  double best_distance = params.max_distance_m;
  for (const std::size_t from : kf) {
    if (chain[to].stamp_s - chain[from].stamp_s < params.min_gap_s) break;
    const SE2 T_from_to = between(chain[from].value, chain[to].value);
    const double distance = std::hypot(T_from_to.x, T_from_to.y);
    if (distance <= best_distance && std::abs(T_from_to.yaw) <= params.max_yaw_rad) {
      best = from;
      best_distance = distance;
    }
  }
  return best;
}

}  // namespace

Eigen::SparseMatrix<double> headingGraphMatrix(
    std::size_t poses, const std::vector<std::pair<std::size_t, std::size_t>>& loops) {
  const auto n = static_cast<Eigen::Index>(poses - 1);
  std::vector<Eigen::Triplet<double>> H;
  auto add = [&](Eigen::Index row, Eigen::Index col, double value) {
    if (row >= 0 && col >= 0) H.emplace_back(row, col, value);
  };
  auto edge = [&](std::size_t a, std::size_t b) {  // unknown index = pose - 1
    const Eigen::Index ia = static_cast<Eigen::Index>(a) - 1, ib = static_cast<Eigen::Index>(b) - 1;
    add(ia, ia, 1.0), add(ib, ib, 1.0), add(ia, ib, -1.0), add(ib, ia, -1.0);
  };
  for (std::size_t i = 0; i + 1 < poses; ++i) edge(i, i + 1);
  for (const auto& [from, to] : loops) edge(from, to);
  Eigen::SparseMatrix<double> A(n, n);
  A.setFromTriplets(H.begin(), H.end());
  return A;
}

std::vector<double> headingCorrections(std::size_t poses, const std::vector<LoopClosure>& loops) {
  std::vector<double> delta(poses, 0.0);
  if (poses < 2 || loops.empty()) return delta;
  // Normal equations of the edges delta_to - delta_from = c (links: c = 0); delta_0 = 0.
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  Eigen::VectorXd g = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(poses - 1));
  for (const LoopClosure& loop : loops) {
    pairs.emplace_back(loop.from, loop.to);
    if (loop.from > 0) g(static_cast<Eigen::Index>(loop.from) - 1) -= loop.heading_correction_rad;
    g(static_cast<Eigen::Index>(loop.to) - 1) += loop.heading_correction_rad;
  }
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(headingGraphMatrix(poses, pairs));
  const Eigen::VectorXd x = solver.solve(g);
  for (Eigen::Index i = 0; i < x.size(); ++i) delta[i + 1] = x(i);
  return delta;
}

LoopCorrection closeLoops(const PoseSeries& T_world_lidar,
                          const std::vector<const Points2*>& points,
                          const LoopClosureParams& params) {
  LoopCorrection out;
  out.T_world_lidar = T_world_lidar;
  const std::vector<std::size_t> kf = keyframes(T_world_lidar, params.keyframe_spacing_s);
  for (const std::size_t to : kf) {
    const auto from = loopPartner(T_world_lidar, kf, to, params);
    if (!from) continue;
    ++out.candidates;
    const SE2 chained = between(T_world_lidar[*from].value, T_world_lidar[to].value);
    const IcpResult direct = matchPointToLine(*points[*from], *points[to], chained, params.icp);
    const double correction = normalizeAngle(direct.T_ref_cur.yaw - chained.yaw);
    if (!direct.converged || std::abs(correction) > params.max_disagreement_rad) {
      ++out.refused;
      continue;
    }
    out.loops.push_back({*from, to, correction});
  }
  if (out.loops.empty()) return out;
  const std::vector<double> delta = headingCorrections(T_world_lidar.size(), out.loops);
  PoseSeries corrected;
  corrected.push_back(T_world_lidar[0].stamp_s, T_world_lidar[0].value);
  for (std::size_t i = 0; i + 1 < T_world_lidar.size(); ++i) {
    const SE2 link = between(T_world_lidar[i].value, T_world_lidar[i + 1].value);
    const double change = delta[i + 1] - delta[i];
    out.max_link_change_rad = std::max(out.max_link_change_rad, std::abs(change));
    corrected.push_back(T_world_lidar[i + 1].stamp_s,
                        corrected[i].value * SE2(link.x, link.y, link.yaw + change));
  }
  out.T_world_lidar = std::move(corrected);
  return out;
}

}  // namespace slamprep::algo
