#include "slamprep/sim/physics/surface_texture.hpp"

#include <cmath>
#include <numbers>
#include <random>

namespace slamprep::sim {

SurfaceTexture::SurfaceTexture(double length_m, std::uint64_t seed) {
  // mt19937_64's output is fixed by the standard, and the draws are made here, not by
  // std::normal_distribution (which is not): the same field with every standard library.
  std::mt19937_64 rng(seed);
  const auto uniform = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };  // [0, 1)
  wave_.reserve(kFeatures);
  phase_.reserve(kFeatures);
  for (int i = 0; i < kFeatures; ++i) {
    const double radius = std::sqrt(-2.0 * std::log(1.0 - uniform()));  // Box-Muller, both parts
    const double angle = 2.0 * std::numbers::pi * uniform();
    wave_.emplace_back(radius * std::cos(angle) / length_m, radius * std::sin(angle) / length_m);
    phase_.push_back(2.0 * std::numbers::pi * uniform());
  }
}

double SurfaceTexture::at(const Eigen::Vector2d& p_world_m) const {
  double sum = 0.0;
  for (int i = 0; i < kFeatures; ++i) sum += std::cos(wave_[i].dot(p_world_m) + phase_[i]);
  return std::sqrt(2.0 / kFeatures) * sum;
}

}  // namespace slamprep::sim
