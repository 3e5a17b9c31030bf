#include "slamprep/algo/calibration/scale_flag.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <cstdio>

namespace slamprep::algo {

std::optional<CommonScale> commonScale(const CalibrationResult& result,
                                       const DiffDriveParams& nominal) {
  if (!result.ok || result.covariance.rows() < 3 || result.covariance.cols() < 3)
    return std::nullopt;
  const Eigen::Vector3d n(nominal.radius_left_m, nominal.radius_right_m, nominal.wheel_base_m);
  const DiffDriveParams& g = result.geometry;
  const Eigen::Vector3d q =
      Eigen::Vector3d(g.radius_left_m, g.radius_right_m, g.wheel_base_m).cwiseQuotient(n);
  const Eigen::Matrix3d D = n.cwiseInverse().asDiagonal();
  const Eigen::Matrix3d C = D * result.covariance.topLeftCorner<3, 3>() * D;
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(C);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0.0).all()) return std::nullopt;
  const Eigen::Vector3d ones = Eigen::Vector3d::Ones();
  const Eigen::Vector3d Ci_ones = ldlt.solve(ones);
  const double information = ones.dot(Ci_ones);
  CommonScale s;
  s.factor = Ci_ones.dot(q) / information;  // Eq. 1
  s.sigma = 1.0 / std::sqrt(information);
  const Eigen::Vector3d r = q - s.factor * ones;
  s.chi2 = r.dot(ldlt.solve(r));  // Eq. 2
  return s;
}

std::optional<NominalFlag> scaleFlag(const CalibrationResult& result,
                                     const DiffDriveParams& nominal,
                                     const ScaleFlagParams& params) {
  const std::optional<CommonScale> s = commonScale(result, nominal);
  if (!s || !(s->chi2 < params.max_chi2) || !(std::abs(s->factor - 1.0) > params.sigmas * s->sigma))
    return std::nullopt;
  const double percent = 100.0 * std::abs(s->factor - 1.0);
  char text[640];
  std::snprintf(text, sizeof text,
                "r_L, r_R and b are all %.2f %% %s the nominal by one factor (%.4f +- %.4f, chi2 "
                "%.1f over 2): a lidar whose ranges read %.2f %% %s gives the same, as does a "
                "nominal geometry wrong by that factor; no comparison of scans, wheels or gyro "
                "tells them apart (the turn per wheel angle r / b is unchanged): measure one "
                "known distance with the lidar, or drive one",
                percent, s->factor > 1.0 ? "above" : "below", s->factor, s->sigma, s->chi2, percent,
                s->factor > 1.0 ? "long" : "short");
  return NominalFlag{"range_scale", s->factor, text};
}

}  // namespace slamprep::algo
