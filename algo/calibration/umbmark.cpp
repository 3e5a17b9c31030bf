#include "slamprep/algo/calibration/umbmark.hpp"

#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace slamprep::algo {
namespace {

// Sample covariance of the mean of a set of 2D errors (zero for fewer than two).
Eigen::Matrix2d covarianceOfMean(const std::vector<Eigen::Vector2d>& e) {
  if (e.size() < 2) return Eigen::Matrix2d::Zero();
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& v : e) mean += v;
  mean /= static_cast<double>(e.size());
  Eigen::Matrix2d cov = Eigen::Matrix2d::Zero();
  for (const auto& v : e) cov += (v - mean) * (v - mean).transpose();
  return cov / static_cast<double>((e.size() - 1) * e.size());
}

// Mean return errors of the cw and ccw runs, (x_cw, y_cw, x_ccw, y_ccw).
using Errors4 = Eigen::Vector4d;

// Return error of a run with its odometry re-integrated from the encoder steps with `geometry`.
Eigen::Vector2d returnError(const UmbmarkRun& run, const DiffDriveParams& geometry) {
  const SE2 odom = integrateSteps(run.steps, geometry.radius_left_m, geometry.radius_right_m,
                                  geometry.wheel_base_m);
  return between(run.T_world_start_true, run.T_world_end_true).translation() - odom.translation();
}

// Centres of gravity: of the recorded odometry (no geometry) or re-integrated with `geometry`.
Errors4 centresOfGravity(const std::vector<UmbmarkRun>& runs, const DiffDriveParams* geometry) {
  Errors4 sum = Errors4::Zero();
  Eigen::Vector2d count = Eigen::Vector2d::Zero();
  for (const UmbmarkRun& run : runs) {
    const Eigen::Vector2d e = geometry ? returnError(run, *geometry) : umbmarkReturnError(run);
    sum.segment<2>(run.clockwise ? 0 : 2) += e;
    count(run.clockwise ? 0 : 1) += 1.0;
  }
  return {sum(0) / count(0), sum(1) / count(0), sum(2) / count(1), sum(3) / count(1)};
}

double relativeChange(const DiffDriveParams& a, const DiffDriveParams& b) {
  return std::max({std::abs(a.radius_left_m / b.radius_left_m - 1.0),
                   std::abs(a.radius_right_m / b.radius_right_m - 1.0),
                   std::abs(a.wheel_base_m / b.wheel_base_m - 1.0)});
}

// The paper's correction of `nominal` by E_d and E_b: c_L = 2 / (E_d + 1), c_R = 2 / (1/E_d + 1)
// keep the mean of the two factors at one (UMBmark cannot observe the mean diameter).
DiffDriveParams corrected(const DiffDriveParams& nominal, double E_d, double E_b) {
  const double c_L = 2.0 / (E_d + 1.0), c_R = 2.0 / (1.0 / E_d + 1.0);
  return {c_L * nominal.radius_left_m, c_R * nominal.radius_right_m, E_b * nominal.wheel_base_m};
}

// Gauss-Newton on the return errors with the odometry re-integrated, in the paper's parameters
// p = (E_d, E_b), from the paper's single step:
//   F(p) = cg(steps integrated with corrected(nominal, p)) + offset     (4 values)
//   p <- p - (J^T J)^-1 J^T F,   J = dF/dp by central differences
// The paper's step is this one with J replaced by the first-order square model A. Iterating with
// A instead converges to wherever A^+ F = 0: with r_L +8 %, r_R -6 %, b +10 % that is a geometry
// leaving 2.3 m of return error (b 19.8 % off), so the exact J is used.
void iterate(const std::vector<UmbmarkRun>& runs, const UmbmarkParams& params,
             const Errors4& offset, UmbmarkResult& result) {
  auto F = [&](const Eigen::Vector2d& p) {
    const DiffDriveParams g = corrected(params.nominal, p(0), p(1));
    return Errors4(centresOfGravity(runs, &g) + offset);
  };
  Eigen::Vector2d p(result.E_d, result.E_b);
  double change = std::numeric_limits<double>::infinity();
  while (change > params.tolerance && result.iterations < params.max_iterations) {
    Eigen::Matrix<double, 4, 2> J;
    for (int j = 0; j < 2; ++j) {
      const Eigen::Vector2d h = 1e-6 * Eigen::Vector2d::Unit(j);
      J.col(j) = (F(p + h) - F(p - h)) / 2e-6;
    }
    const Eigen::Vector2d next = p - J.colPivHouseholderQr().solve(F(p));
    ++result.iterations;
    result.condition_number = equilibratedConditionNumber(J);
    if (!next.allFinite() || !(next(0) > 0.0) || !(next(1) > 0.0)) {
      result.ok = false;
      result.reason = "UMBmark iteration " + std::to_string(result.iterations) +
                      " left the valid geometries (E_d = " + std::to_string(next(0)) +
                      ", E_b = " + std::to_string(next(1)) + ")";
      return;
    }
    change = relativeChange(corrected(params.nominal, next(0), next(1)), result.geometry);
    p = next;
    result.geometry = corrected(params.nominal, p(0), p(1));
  }
  result.E_d = p(0);
  result.E_b = p(1);
  if (change > params.tolerance) {
    result.ok = false;
    result.reason = "UMBmark's iterated correction did not converge in " +
                    std::to_string(params.max_iterations) + " corrections (last update " +
                    std::to_string(change) + " relative)";
  }
}

// The paper's single step on the recorded odometry; then, when every run has its encoder steps,
// the iteration. `offset` is added to every centre of gravity (the covariance perturbs it).
UmbmarkResult correct(const std::vector<UmbmarkRun>& runs, const UmbmarkParams& params,
                      const Errors4& offset) {
  const Errors4 cg = centresOfGravity(runs, nullptr) + offset;
  UmbmarkResult result = umbmarkFromErrors(cg.head<2>(), cg.tail<2>(), params);
  result.first_order = result.geometry;
  result.iterations = 1;
  const bool steps = std::all_of(runs.begin(), runs.end(),
                                 [](const UmbmarkRun& run) { return !run.steps.empty(); });
  if (result.ok && steps && params.max_iterations > 1) iterate(runs, params, offset, result);
  return result;
}

}  // namespace

Eigen::Vector2d umbmarkReturnError(const UmbmarkRun& run) {
  return between(run.T_world_start_true, run.T_world_end_true).translation() -
         between(run.T_world_start_odom, run.T_world_end_odom).translation();
}

UmbmarkResult umbmarkFromErrors(const Eigen::Vector2d& cg_cw, const Eigen::Vector2d& cg_ccw,
                                const UmbmarkParams& params) {
  UmbmarkResult result;
  result.cg_cw = cg_cw;
  result.cg_ccw = cg_ccw;
  const double L = params.side_m, b = params.nominal.wheel_base_m;
  // First-order return errors, start at the origin facing +x, each leg bending by beta, each
  // turn short by alpha (derivation in docs/calibration.md):
  //   cw:  x = y = -2L (beta + alpha);   ccw: x = 2L (beta - alpha), y = -2L (beta - alpha).
  // Borenstein & Feng 1996: alpha = (x_cw + x_ccw) / (-4L), beta = (x_cw - x_ccw) / (-4L), and
  // from y: alpha = (y_cw - y_ccw) / (-4L), beta = (y_cw + y_ccw) / (-4L). Both are averaged.
  result.alpha_rad = 0.5 * ((cg_cw.x() + cg_ccw.x()) + (cg_cw.y() - cg_ccw.y())) / (-4.0 * L);
  result.beta_rad = 0.5 * ((cg_cw.x() - cg_ccw.x()) + (cg_cw.y() + cg_ccw.y())) / (-4.0 * L);
  // The map (alpha, beta) -> (x_cw, y_cw, x_ccw, y_ccw) has orthogonal columns of equal norm.
  result.condition_number = 1.0;
  // R = (L/2) / sin(beta/2); E_d = (R + b/2) / (R - b/2) = (L + b s) / (L - b s), s = sin(beta/2)
  // (the second form has no division by zero at beta = 0).
  const double s = std::sin(0.5 * result.beta_rad);
  const double half_pi = 0.5 * std::numbers::pi;
  if (!(L - b * std::abs(s) > 0.0) || !(std::abs(result.alpha_rad) < half_pi)) {
    result.reason = "return errors too large for UMBmark's first-order model (alpha = " +
                    std::to_string(result.alpha_rad) +
                    " rad, beta = " + std::to_string(result.beta_rad) + " rad)";
    return result;
  }
  result.E_d = (L + b * s) / (L - b * s);
  result.E_b = half_pi / (half_pi - result.alpha_rad);  // E_b = 90 deg / (90 deg - alpha)
  result.geometry = corrected(params.nominal, result.E_d, result.E_b);
  result.ok = true;
  return result;
}

UmbmarkResult calibrateUmbmark(const std::vector<UmbmarkRun>& runs, const UmbmarkParams& params) {
  int cw = 0, ccw = 0;
  for (const UmbmarkRun& run : runs) ++(run.clockwise ? cw : ccw);
  if (cw == 0 || ccw == 0 || !(params.side_m > 0.0)) {
    UmbmarkResult result;
    result.reason = !(params.side_m > 0.0)
                        ? "square side must be positive"
                        : "UMBmark needs clockwise and counter-clockwise square runs (have " +
                              std::to_string(cw) + " cw, " + std::to_string(ccw) + " ccw)";
    return result;
  }
  UmbmarkResult result = correct(runs, params, Errors4::Zero());
  result.intervals_used = static_cast<int>(runs.size());
  if (!result.ok || cw < 2 || ccw < 2) return result;
  // Covariance: the scatter of the runs' return errors through the (central-difference) Jacobian
  // of the whole correction, iterations included.
  std::vector<Eigen::Vector2d> e_cw, e_ccw;
  for (const UmbmarkRun& run : runs)
    (run.clockwise ? e_cw : e_ccw).push_back(umbmarkReturnError(run));
  Eigen::Matrix4d cov_cg = Eigen::Matrix4d::Zero();
  cov_cg.topLeftCorner<2, 2>() = covarianceOfMean(e_cw);
  cov_cg.bottomRightCorner<2, 2>() = covarianceOfMean(e_ccw);
  Eigen::Matrix<double, 3, 4> D;
  for (int j = 0; j < 4; ++j) {
    const double h = 1e-7 * std::max(1.0, params.side_m);
    const Errors4 dx = h * Errors4::Unit(j);
    const auto gp = correct(runs, params, dx).geometry;
    const auto gm = correct(runs, params, -dx).geometry;
    D.col(j) =
        Eigen::Vector3d(gp.radius_left_m - gm.radius_left_m, gp.radius_right_m - gm.radius_right_m,
                        gp.wheel_base_m - gm.wheel_base_m) /
        (2 * h);
  }
  result.covariance = D * cov_cg * D.transpose();
  return result;
}

}  // namespace slamprep::algo
