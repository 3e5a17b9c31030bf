#include "slamprep/algo/matching/icp.hpp"

#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <string>

#include "slamprep/core/rigid_alignment.hpp"

namespace slamprep::algo {
namespace {

/// One correspondence: current point (cur frame), reference point, line normal (p2l only).
struct Pair {
  Eigen::Vector2d p_cur;
  Eigen::Vector2d q_ref;
  Eigen::Vector2d n_ref;
  double error_sq = 0.0;  ///< squared residual at the estimate the pair was found with
};

using Line = std::pair<Eigen::Vector2d, Eigen::Vector2d>;  // (centroid, unit normal)

/// Line through `neighbors` (principal axis of their scatter), or nullopt when fewer than three
/// or no line (a corner, a blob: sqrt(lambda_min / lambda_max) above line_max_thickness).
std::optional<Line> fitLine(const Points2& points, const std::vector<std::size_t>& neighbors,
                            const IcpParams& params) {
  if (neighbors.size() < 3) return std::nullopt;
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (std::size_t i : neighbors) mean += points[i];
  mean /= static_cast<double>(neighbors.size());
  Eigen::Matrix2d scatter = Eigen::Matrix2d::Zero();
  for (std::size_t i : neighbors) scatter += (points[i] - mean) * (points[i] - mean).transpose();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eig;
  eig.computeDirect(scatter);
  const Eigen::Vector2d lambda = eig.eigenvalues();  // ascending
  const double thickness_sq = params.line_max_thickness * params.line_max_thickness;
  if (lambda(1) <= 0.0 || lambda(0) > thickness_sq * lambda(1)) return std::nullopt;
  return Line{mean, eig.eigenvectors().col(0)};
}

/// Neighbours of point i for its line: its index neighbours i-h..i+h when they are within
/// line_max_radius (points in scan order, as Censi's PL-ICP uses them: no search needed),
/// otherwise its nearest neighbours from the kd-tree (gaps, unordered point sets).
std::vector<std::size_t> lineNeighbors(const KdTree2& tree, std::size_t i, const IcpParams& params,
                                       std::vector<std::size_t>& scratch) {
  const Points2& points = tree.points();
  const double radius_sq = params.line_max_radius_m * params.line_max_radius_m;
  const std::size_t half = params.line_neighbors / 2;
  scratch.clear();
  if (i >= half && i + half < points.size()) {
    for (std::size_t j = i - half; j <= i + half; ++j)
      if ((points[j] - points[i]).squaredNorm() <= radius_sq) scratch.push_back(j);
    if (scratch.size() == 2 * half + 1) return scratch;
  }
  scratch.clear();
  Neighbor found[KdTree2::kMaxInto];
  const std::size_t n = tree.nearestInto(points[i], params.line_neighbors, found);
  for (std::size_t j = 0; j < n; ++j)
    if (found[j].distance_sq_m2 <= radius_sq) scratch.push_back(found[j].index);
  return scratch;
}

/// Nearest-neighbour correspondences at the estimate T, gated and trimmed.
/// What the last search of one current point found. Its nearest reference point stays the nearest
/// while the query moves less than `slack` = (d2 - d1) / 2 (d1, d2: distances to the nearest and
/// second nearest): every other point stays farther than d2 - m >= d1 + m (triangle inequality).
/// Late ICP rounds move points by well under a millimetre, so most searches are skipped, exactly.
struct NearestCache {
  std::uint32_t index = 0;
  double slack_m = -1.0;  ///< < 0: nothing cached
  Eigen::Vector2d query = Eigen::Vector2d::Zero();
};

/// The nearest reference point to `query`, from the cache when provably unchanged.
Neighbor cachedNearest(const KdTree2& tree, const Eigen::Vector2d& query, NearestCache& cache) {
  if (cache.slack_m > 0.0 && (query - cache.query).squaredNorm() < cache.slack_m * cache.slack_m)
    return {cache.index, (tree.points()[cache.index] - query).squaredNorm()};
  Neighbor two[2];
  const std::size_t found = tree.nearestInto(query, 2, two);
  cache.index = static_cast<std::uint32_t>(two[0].index);
  cache.query = query;
  cache.slack_m = found < 2
                      ? std::numeric_limits<double>::infinity()
                      : 0.5 * (std::sqrt(two[1].distance_sq_m2) - std::sqrt(two[0].distance_sq_m2));
  return two[0];
}

/// Drops the pairs whose residual exceeds `sigmas` robust sigmas (1.4826 MAD of |residual|).
void gateOutliers(std::vector<Pair>& pairs, double sigmas) {
  if (sigmas <= 0.0 || pairs.empty()) return;
  std::vector<double> error_sq(pairs.size());
  std::transform(pairs.begin(), pairs.end(), error_sq.begin(),
                 [](const Pair& p) { return p.error_sq; });
  const auto mid = error_sq.begin() + static_cast<std::ptrdiff_t>(error_sq.size() / 2);
  std::nth_element(error_sq.begin(), mid, error_sq.end());
  const double gate = sigmas * 1.4826 * std::sqrt(*mid);
  if (gate <= 0.0) return;  // more than half exact: keep everything rather than the exact ones
  std::erase_if(pairs, [&](const Pair& p) { return p.error_sq > gate * gate; });
}

/// Trimmed ICP: keeps the best (1 - fraction) of the pairs.
void trimWorst(std::vector<Pair>& pairs, double fraction) {
  const auto keep = static_cast<std::size_t>(
      std::ceil((1.0 - std::clamp(fraction, 0.0, 1.0)) * static_cast<double>(pairs.size())));
  if (keep >= pairs.size()) return;
  std::nth_element(pairs.begin(), pairs.begin() + static_cast<std::ptrdiff_t>(keep), pairs.end(),
                   [](const Pair& a, const Pair& b) { return a.error_sq < b.error_sq; });
  pairs.resize(keep);
}

/// Every `stride`-th current point takes part; `cache` holds one entry per current point.
std::vector<Pair> findPairs(const IcpReference& ref, const Points2& cur, std::size_t stride,
                            const SE2& T, bool point_to_line, const IcpParams& params,
                            std::vector<NearestCache>& cache) {
  std::vector<Pair> pairs;
  pairs.reserve(cur.size() / stride + 1);
  const double gate_sq =
      params.max_correspondence_distance_m * params.max_correspondence_distance_m;
  const Eigen::Matrix2d R = T.rotation();
  const Eigen::Vector2d t = T.translation();
  for (std::size_t i = 0; i < cur.size(); i += stride) {
    const Eigen::Vector2d& p = cur[i];
    const Eigen::Vector2d p_ref = R * p + t;
    if (ref.points().empty()) break;
    const Neighbor nn = cachedNearest(ref.tree(), p_ref, cache[i]);
    if (nn.distance_sq_m2 > gate_sq) continue;
    Pair pair{p, ref.points()[nn.index], Eigen::Vector2d::Zero(), nn.distance_sq_m2};
    if (point_to_line) {
      pair.n_ref = ref.normal(nn.index);
      if (pair.n_ref.isZero()) continue;
      pair.q_ref = ref.linePoint(nn.index);  // the fitted line's centroid: less noisy
      const double e = pair.n_ref.dot(p_ref - pair.q_ref);
      pair.error_sq = e * e;
    }
    pairs.push_back(pair);
  }
  gateOutliers(pairs, params.outlier_sigmas);
  trimWorst(pairs, params.trim_fraction);
  return pairs;
}

/// Closed-form point-to-point step from pairs (docs/design.md#point-to-point-icp):
/// core/rigid_alignment.hpp's solution of argmin_T sum |q - T p|^2.
std::optional<SE2> solvePointToPoint(const std::vector<Pair>& pairs) {
  std::vector<Eigen::Vector2d> p_cur(pairs.size()), q_ref(pairs.size());
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    p_cur[i] = pairs[i].p_cur;
    q_ref[i] = pairs[i].q_ref;
  }
  return solveRigid2D(p_cur, q_ref).T_q_p;
}

/// Largest real root of the monic-free quartic c4 x^4 + ... + c0 (companion-matrix eigenvalues).
std::optional<double> largestRealRoot(const Eigen::Matrix<double, 5, 1>& c) {
  Eigen::Matrix4d companion = Eigen::Matrix4d::Zero();
  companion.block<3, 3>(1, 0).setIdentity();
  for (int i = 0; i < 4; ++i) companion(i, 3) = -c(i) / c(4);
  const Eigen::Vector4cd roots =
      Eigen::EigenSolver<Eigen::Matrix4d>(companion, false).eigenvalues();
  std::optional<double> best;
  for (int i = 0; i < 4; ++i) {
    const double scale = std::max(1.0, std::abs(roots(i)));
    if (std::abs(roots(i).imag()) > 1e-6 * scale) continue;
    if (!best || roots(i).real() > *best) best = roots(i).real();
  }
  return best;
}

/// Exact point-to-line step (Censi 2008). With x = (t_x, t_y, cos th, sin th) every residual
/// n^T (R p + t - q) is linear in x: a^T x - b, a = M_p^T n, M_p = [[1,0,px,-py],[0,1,py,px]].
/// Minimise x^T M x + g^T x subject to cos^2 + sin^2 = 1 (one Lagrange multiplier, a quartic).
std::optional<SE2> solvePointToLine(const std::vector<Pair>& pairs) {
  if (pairs.size() < 3) return std::nullopt;
  Eigen::Matrix4d M = Eigen::Matrix4d::Zero();
  Eigen::Vector4d g = Eigen::Vector4d::Zero();
  for (const Pair& pr : pairs) {
    const Eigen::Vector2d& p = pr.p_cur;
    const Eigen::Vector2d& n = pr.n_ref;
    const Eigen::Vector4d a(n.x(), n.y(), n.x() * p.x() + n.y() * p.y(),
                            -n.x() * p.y() + n.y() * p.x());
    M.noalias() += a * a.transpose();
    g -= 2.0 * n.dot(pr.q_ref) * a;
  }
  const Eigen::Matrix2d A = M.topLeftCorner<2, 2>(), B = M.topRightCorner<2, 2>(),
                        D = M.bottomRightCorner<2, 2>();
  // Translation eliminated: t(c) = -A^-1 (B c + g_t / 2).
  if (std::abs(A.determinant()) <= 1e-12 * A.squaredNorm()) return std::nullopt;
  const Eigen::Matrix2d A_inv = A.inverse();
  const Eigen::Matrix2d S = D - B.transpose() * A_inv * B;                      // c^T S c
  const Eigen::Vector2d h = g.tail<2>() - B.transpose() * A_inv * g.head<2>();  // + h^T c
  // Stationarity 2 (S + l I) c = -h with |c| = 1: using adj(S + l I) = adj(S) + l I,
  // |(adj(S) + l I) h|^2 = 4 det(S + l I)^2 is a quartic in l; the minimum is its largest root.
  const Eigen::Matrix2d G = (Eigen::Matrix2d() << S(1, 1), -S(0, 1), -S(1, 0), S(0, 0)).finished();
  const double p1 = S.trace(), p0 = S.determinant();
  const Eigen::Vector2d Gh = G * h;
  Eigen::Matrix<double, 5, 1> c;
  c << 4.0 * p0 * p0 - Gh.squaredNorm(), 8.0 * p1 * p0 - 2.0 * h.dot(Gh),
      4.0 * (p1 * p1 + 2.0 * p0) - h.squaredNorm(), 8.0 * p1, 4.0;
  const auto lambda = largestRealRoot(c);
  if (!lambda) return std::nullopt;
  const Eigen::Matrix2d P = S + *lambda * Eigen::Matrix2d::Identity();
  Eigen::Vector2d cs = -(G + *lambda * Eigen::Matrix2d::Identity()) * h;  // = -adj(P) h
  if (P.determinant() < 0.0) cs = -cs;  // c = -adj(P) h / (2 det P): only the direction matters
  if (cs.norm() <= 0.0) return std::nullopt;
  cs.normalize();
  const Eigen::Vector2d t = -A_inv * (B * cs + 0.5 * g.head<2>());
  return SE2(t.x(), t.y(), std::atan2(cs.y(), cs.x()));
}

/// Var(x | |x| < z) / Var(x) for a Gaussian cut symmetrically so that `trim` of it is dropped:
/// 1 - 2 z phi(z) / (1 - trim), z = Phi^-1(1 - trim / 2). Undoes trimming's shrinking of sigma^2.
double trimmedVarianceFactor(double trim) {
  trim = std::clamp(trim, 0.0, 0.9);
  if (trim <= 0.0) return 1.0;
  double lo = 0.0, hi = 10.0;  // bisection on erf(z / sqrt 2) = 1 - trim
  for (int i = 0; i < 60; ++i) {
    const double z = 0.5 * (lo + hi);
    (std::erf(z / std::sqrt(2.0)) < 1.0 - trim ? lo : hi) = z;
  }
  const double z = 0.5 * (lo + hi);
  const double phi = std::exp(-0.5 * z * z) / std::sqrt(2.0 * std::numbers::pi);
  return 1.0 - 2.0 * z * phi / (1.0 - trim);
}

/// The fraction of Gaussian residuals the gate and the trim drop together.
double droppedFraction(const IcpParams& params) {
  const double gated =
      params.outlier_sigmas > 0.0 ? std::erfc(params.outlier_sigmas / std::sqrt(2.0)) : 0.0;
  return gated + (1.0 - gated) * std::clamp(params.trim_fraction, 0.0, 1.0);
}

/// sigma^2 (J^T J)^-1 with J the residual Jacobian w.r.t. (x, y, yaw) at T; sigma^2 from residuals.
Eigen::Matrix3d covarianceAt(const std::vector<Pair>& pairs, const SE2& T, bool point_to_line,
                             const IcpParams& params, double* rms) {
  Eigen::Matrix3d info = Eigen::Matrix3d::Zero();
  double sum_sq = 0.0;
  const Eigen::Matrix2d R = T.rotation();
  for (const Pair& pr : pairs) {
    const Eigen::Vector2d Rp = R * pr.p_cur;
    Eigen::Matrix<double, 2, 3> J;  // d(R p + t)/d(x, y, yaw)
    J << 1.0, 0.0, -Rp.y(), 0.0, 1.0, Rp.x();
    const Eigen::Vector2d e = Rp + T.translation() - pr.q_ref;
    if (point_to_line) {
      const Eigen::RowVector3d j = pr.n_ref.transpose() * J;
      info.noalias() += j.transpose() * j;
      sum_sq += std::pow(pr.n_ref.dot(e), 2);
    } else {
      info.noalias() += J.transpose() * J;
      sum_sq += e.squaredNorm();
    }
  }
  const double n_res = static_cast<double>(pairs.size()) * (point_to_line ? 1.0 : 2.0);
  *rms = pairs.empty() ? 0.0 : std::sqrt(sum_sq / n_res);
  const double sigma_sq =
      n_res > 3.0 ? sum_sq / (n_res - 3.0) / trimmedVarianceFactor(droppedFraction(params))
                  : params.max_variance;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(info);
  Eigen::Vector3d variances;
  for (int i = 0; i < 3; ++i) {
    const double l = eig.eigenvalues()(i);
    variances(i) = l > sigma_sq / params.max_variance ? sigma_sq / l : params.max_variance;
  }
  return eig.eigenvectors() * variances.asDiagonal() * eig.eigenvectors().transpose();
}

/// Mean squared residual of the pairs at T (what the step minimised).
double meanSquaredResidual(const std::vector<Pair>& pairs, const SE2& T, bool point_to_line) {
  double sum = 0.0;
  const Eigen::Matrix2d R = T.rotation();
  for (const Pair& pr : pairs) {
    const Eigen::Vector2d e = R * pr.p_cur + T.translation() - pr.q_ref;
    sum += point_to_line ? std::pow(pr.n_ref.dot(e), 2) : e.squaredNorm();
  }
  return pairs.empty() ? 0.0 : sum / static_cast<double>(pairs.size());
}

bool small(const SE2& step, const IcpParams& params) {
  return step.translation().norm() < params.translation_tolerance_m &&
         std::abs(step.yaw) < params.rotation_tolerance_rad;
}

IcpResult match(const IcpReference& ref, const Points2& cur, const SE2& guess, bool point_to_line,
                const IcpParams& params) {
  IcpResult result;
  result.T_ref_cur = guess;
  if (point_to_line && !ref.hasNormals()) {
    result.reason = "reference has no line normals (build IcpReference with normals)";
    return result;
  }
  // Recent estimates with their cost: nearest-neighbour ICP can end in a limit cycle between a
  // few correspondence sets; revisiting an estimate means converged, to the cheapest of the cycle.
  constexpr std::size_t kHistory = 6;
  std::vector<std::pair<SE2, double>> history;
  std::vector<Pair> pairs;
  // Coarse to fine: every coarse_stride-th current point while the steps are large.
  const std::size_t stride = std::max<std::size_t>(1, params.coarse_stride);
  bool fine = stride == 1 || cur.size() / stride < params.min_inliers;
  std::vector<NearestCache> cache(cur.size());
  for (result.iterations = 1; result.iterations <= params.max_iterations; ++result.iterations) {
    pairs = findPairs(ref, cur, fine ? 1 : stride, result.T_ref_cur, point_to_line, params, cache);
    if (pairs.size() < params.min_inliers) {
      result.reason = "only " + std::to_string(pairs.size()) + " correspondences (need " +
                      std::to_string(params.min_inliers) + "): too little overlap or a bad guess";
      break;
    }
    const auto T_new = point_to_line ? solvePointToLine(pairs) : solvePointToPoint(pairs);
    if (!T_new) {
      result.reason = "degenerate correspondences: the step is not determined";
      break;
    }
    const SE2 step = between(result.T_ref_cur, *T_new);
    result.T_ref_cur = *T_new;
    if (!fine) {
      fine = step.translation().norm() < params.coarse_until_m &&
             std::abs(step.yaw) < params.coarse_until_rad;
      continue;
    }
    if (small(step, params)) {
      result.converged = true;
      break;
    }
    const double cost = meanSquaredResidual(pairs, *T_new, point_to_line);
    const auto seen = std::find_if(history.begin(), history.end(), [&](const auto& h) {
      return small(between(h.first, *T_new), params);
    });
    if (seen != history.end()) {  // a limit cycle: take its cheapest member
      const auto best = std::min_element(
          seen, history.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
      if (best->second < cost) result.T_ref_cur = best->first;
      pairs = findPairs(ref, cur, 1, result.T_ref_cur, point_to_line, params, cache);
      result.converged = true;
      break;
    }
    history.emplace_back(*T_new, cost);
    if (history.size() > kHistory) history.erase(history.begin());
  }
  if (!result.converged && result.reason.empty()) {
    result.iterations = params.max_iterations;
    result.reason = "no convergence in " + std::to_string(params.max_iterations) + " iterations";
  }
  result.inliers = pairs.size();
  result.covariance =
      covarianceAt(pairs, result.T_ref_cur, point_to_line, params, &result.rms_residual_m);
  return result;
}

}  // namespace

IcpReference::IcpReference(Points2 ref, const IcpParams& params, bool with_normals)
    : tree_(std::move(ref)) {
  if (!with_normals) return;
  normals_.reserve(tree_.size());
  line_points_.reserve(tree_.size());
  std::vector<std::size_t> scratch;
  for (std::size_t i = 0; i < tree_.size(); ++i) {
    const auto line = fitLine(tree_.points(), lineNeighbors(tree_, i, params, scratch), params);
    normals_.push_back(line ? line->second : Eigen::Vector2d::Zero());
    line_points_.push_back(line ? line->first : tree_.points()[i]);
  }
}

std::optional<SE2> alignPointToPoint(const Points2& p, const Points2& q) {
  assert(p.size() == q.size());
  std::vector<Pair> pairs;
  for (std::size_t i = 0; i < p.size(); ++i)
    pairs.push_back({p[i], q[i], Eigen::Vector2d::Zero(), 0.0});
  return solvePointToPoint(pairs);
}

IcpResult matchPointToPoint(const IcpReference& ref, const Points2& cur, const SE2& T_ref_cur_guess,
                            const IcpParams& params) {
  return match(ref, cur, T_ref_cur_guess, false, params);
}

IcpResult matchPointToPoint(const Points2& ref, const Points2& cur, const SE2& T_ref_cur_guess,
                            const IcpParams& params) {
  return match(IcpReference(ref, params, false), cur, T_ref_cur_guess, false, params);
}

IcpResult matchPointToLine(const IcpReference& ref, const Points2& cur, const SE2& T_ref_cur_guess,
                           const IcpParams& params) {
  return match(ref, cur, T_ref_cur_guess, true, params);
}

IcpResult matchPointToLine(const Points2& ref, const Points2& cur, const SE2& T_ref_cur_guess,
                           const IcpParams& params) {
  return match(IcpReference(ref, params, true), cur, T_ref_cur_guess, true, params);
}

}  // namespace slamprep::algo
