#include "slamprep/eval/metrics/consistency.hpp"

#include <Eigen/Cholesky>
#include <cassert>
#include <cmath>

namespace slamprep::eval {

ErrorConsistency errorConsistency(const std::vector<double>& errors,
                                  const std::vector<double>& sigmas) {
  assert(errors.size() == sigmas.size() && !errors.empty());
  ErrorConsistency out;
  out.n = static_cast<int>(errors.size());
  double sum = 0.0, sq = 0.0;
  int in1 = 0, in3 = 0;
  for (std::size_t i = 0; i < errors.size(); ++i) {
    sum += errors[i];
    sq += errors[i] * errors[i];
    in1 += std::abs(errors[i]) <= sigmas[i];
    in3 += std::abs(errors[i]) <= 3.0 * sigmas[i];
  }
  out.bias = sum / out.n;
  out.rms = std::sqrt(sq / out.n);
  double dev = 0.0;
  for (double e : errors) dev += (e - out.bias) * (e - out.bias);
  out.std = out.n > 1 ? std::sqrt(dev / (out.n - 1)) : 0.0;
  out.coverage_1sigma = static_cast<double>(in1) / out.n;
  out.coverage_3sigma = static_cast<double>(in3) / out.n;
  return out;
}

std::optional<double> normalizedErrorSquared(const Eigen::VectorXd& error,
                                             const Eigen::MatrixXd& covariance) {
  if (covariance.rows() != error.size() || covariance.cols() != error.size() || error.size() == 0)
    return std::nullopt;
  // Scaled to unit diagonal first: the parameters mix m^2 and rad^2 entries many decades apart.
  const Eigen::ArrayXd d = covariance.diagonal().array();
  if (!(d > 0.0).all()) return std::nullopt;
  const Eigen::VectorXd inv_s = d.sqrt().inverse().matrix();
  const Eigen::MatrixXd P = inv_s.asDiagonal() * covariance * inv_s.asDiagonal();
  const Eigen::LLT<Eigen::MatrixXd> llt(0.5 * (P + P.transpose()));
  if (llt.info() != Eigen::Success) return std::nullopt;
  const Eigen::VectorXd e = error.cwiseProduct(inv_s);
  const double nees = e.dot(llt.solve(e));
  if (!std::isfinite(nees)) return std::nullopt;
  return nees;
}

}  // namespace slamprep::eval
