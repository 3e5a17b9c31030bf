#include "algo/calibration/umbmark.hpp"

#include <cmath>
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
  // Corrections keeping the mean diameter: c_L = 2 / (E_d + 1), c_R = 2 / (1/E_d + 1).
  const double c_L = 2.0 / (result.E_d + 1.0), c_R = 2.0 / (1.0 / result.E_d + 1.0);
  result.geometry = {c_L * params.nominal.radius_left_m, c_R * params.nominal.radius_right_m,
                     result.E_b * b};
  result.ok = true;
  return result;
}

UmbmarkResult calibrateUmbmark(const std::vector<UmbmarkRun>& runs, const UmbmarkParams& params) {
  std::vector<Eigen::Vector2d> cw, ccw;
  for (const UmbmarkRun& run : runs) (run.clockwise ? cw : ccw).push_back(umbmarkReturnError(run));
  if (cw.empty() || ccw.empty() || !(params.side_m > 0.0)) {
    UmbmarkResult result;
    result.reason = !(params.side_m > 0.0)
                        ? "square side must be positive"
                        : "UMBmark needs clockwise and counter-clockwise square runs (have " +
                              std::to_string(cw.size()) + " cw, " + std::to_string(ccw.size()) +
                              " ccw)";
    return result;
  }
  auto mean = [](const std::vector<Eigen::Vector2d>& e) {
    Eigen::Vector2d m = Eigen::Vector2d::Zero();
    for (const auto& v : e) m += v;
    return Eigen::Vector2d(m / static_cast<double>(e.size()));
  };
  const Eigen::Vector2d cg_cw = mean(cw), cg_ccw = mean(ccw);
  UmbmarkResult result = umbmarkFromErrors(cg_cw, cg_ccw, params);
  result.intervals_used = static_cast<int>(runs.size());
  if (!result.ok || cw.size() < 2 || ccw.size() < 2) return result;
  // Covariance: the scatter of the runs through the (central-difference) Jacobian.
  Eigen::Matrix4d cov_cg = Eigen::Matrix4d::Zero();
  cov_cg.topLeftCorner<2, 2>() = covarianceOfMean(cw);
  cov_cg.bottomRightCorner<2, 2>() = covarianceOfMean(ccw);
  Eigen::Vector4d cg;
  cg << cg_cw, cg_ccw;
  Eigen::Matrix<double, 3, 4> D;
  for (int j = 0; j < 4; ++j) {
    const double h = 1e-7 * std::max(1.0, params.side_m);
    Eigen::Vector4d up = cg, dn = cg;
    up(j) += h;
    dn(j) -= h;
    const auto gp = umbmarkFromErrors(up.head<2>(), up.tail<2>(), params).geometry;
    const auto gm = umbmarkFromErrors(dn.head<2>(), dn.tail<2>(), params).geometry;
    D.col(j) =
        Eigen::Vector3d(gp.radius_left_m - gm.radius_left_m, gp.radius_right_m - gm.radius_right_m,
                        gp.wheel_base_m - gm.wheel_base_m) /
        (2 * h);
  }
  result.covariance = D * cov_cg * D.transpose();
  return result;
}

}  // namespace slamprep::algo
