#include "slamprep/algo/calibration/against_nominal.hpp"

#include <Eigen/Cholesky>
#include <cmath>
#include <numbers>

namespace slamprep::algo {

double chi2Survival3(double x) {
  if (!(x > 0.0)) return 1.0;
  return std::erfc(std::sqrt(0.5 * x)) +
         std::sqrt(2.0 * x / std::numbers::pi) * std::exp(-0.5 * x);  // Eq. 2
}

std::optional<NominalTest> nominalTest(const CalibrationResult& result,
                                       const DiffDriveParams& nominal,
                                       const NominalTestParams& params) {
  if (!result.ok || result.covariance.rows() < 3 || result.covariance.cols() < 3)
    return std::nullopt;
  const Eigen::Matrix3d C = result.covariance.topLeftCorner<3, 3>();
  const Eigen::LDLT<Eigen::Matrix3d> ldlt(C);
  if (ldlt.info() != Eigen::Success || !(ldlt.vectorD().array() > 0.0).all()) return std::nullopt;
  const DiffDriveParams& g = result.geometry;
  const Eigen::Vector3d d(g.radius_left_m - nominal.radius_left_m,
                          g.radius_right_m - nominal.radius_right_m,
                          g.wheel_base_m - nominal.wheel_base_m);
  NominalTest t;
  t.chi2 = d.dot(ldlt.solve(d));  // Eq. 1
  t.p = chi2Survival3(t.chi2);
  t.z = d.cwiseQuotient(C.diagonal().cwiseSqrt());
  t.shows_nominal_wrong = t.p < params.alpha;
  return t;
}

}  // namespace slamprep::algo
