#pragma once
// A range error fixed in the world: a stationary Gaussian field over the plane, evaluated where a
// beam hits, so every scan that sees a spot again sees the same error there (real lidars' error
// is mostly the surface's, not the scan's: docs/simulate.md, "Range noise").

#include <Eigen/Core>
#include <cstdint>
#include <vector>

namespace slamprep::sim {

/// Random Fourier features (Rahimi and Recht 2007): with K wave vectors k_i ~ N(0, I / l^2) and
/// phases phi_i ~ U[0, 2 pi),
///   f(p) = sqrt(2 / K) sum_i cos(k_i . p + phi_i)                                      (1)
/// has mean 0 and variance 1 at every p, and its covariance tends to exp(-|d|^2 / (2 l^2))
/// (Bochner's theorem: the Gaussian kernel's spectrum is the Gaussian the k_i are drawn from).
class SurfaceTexture {
 public:
  static constexpr int kFeatures = 64;
  /// The field of correlation length `length_m`, drawn from `seed`.
  SurfaceTexture(double length_m, std::uint64_t seed);
  /// Eq. (1): the field at `p_world_m`.
  double at(const Eigen::Vector2d& p_world_m) const;

 private:
  std::vector<Eigen::Vector2d> wave_;  ///< k_i [rad/m]
  std::vector<double> phase_;          ///< phi_i
};

}  // namespace slamprep::sim
