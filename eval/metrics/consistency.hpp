#pragma once
// Is a reported uncertainty honest? Statistics of signed errors and their reported sigmas over
// repeated runs (seeds) of one experiment (docs/metrics.md, "Consistency").

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace slamprep::eval {

/// One parameter over n runs; errors and sigmas in the same unit.
struct ErrorConsistency {
  int n = 0;
  double bias = 0.0;             ///< mean signed error
  double std = 0.0;              ///< sample standard deviation (n - 1) of the signed error
  double rms = 0.0;              ///< sqrt(mean error^2) = sqrt(bias^2 + (n-1)/n std^2)
  double coverage_1sigma = 0.0;  ///< fraction of runs with |error| <= 1 sigma
  double coverage_3sigma = 0.0;  ///< fraction of runs with |error| <= 3 sigma

  bool operator==(const ErrorConsistency&) const = default;
};

/// Statistics of `errors` against their reported 1-sigma `sigmas` (equal lengths, at least one
/// run). For an honest Gaussian estimate coverage_1sigma -> 0.683 and coverage_3sigma -> 0.997.
ErrorConsistency errorConsistency(const std::vector<double>& errors,
                                  const std::vector<double>& sigmas);

/// Normalised estimation error squared e^T P^-1 e (chi-square with dim(e) degrees of freedom for
/// an honest covariance P). Computed on P scaled to unit diagonal and
/// symmetrised; nullopt when that is not positive definite or the sizes differ.
std::optional<double> normalizedErrorSquared(const Eigen::VectorXd& error,
                                             const Eigen::MatrixXd& covariance);

}  // namespace slamprep::eval
