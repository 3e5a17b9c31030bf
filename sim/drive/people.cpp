#include "slamprep/sim/drive/people.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "slamprep/sim/physics/transients.hpp"

namespace slamprep::sim {
namespace {

Eigen::Vector2d keptAway(Eigen::Vector2d o) {
  const double n = o.norm();
  if (n >= People::kNearestM) return o;
  return n > 0.0 ? Eigen::Vector2d(o * (People::kNearestM / n))
                 : Eigen::Vector2d(People::kNearestM, 0.0);
}

}  // namespace

People::People(const PeopleConfig& config, std::uint64_t seed)
    : config_(config), rng_(seed), a_(std::exp(-kStepS / config.correlation_s)) {
  assert(config.count >= 0 && config.distance_m > 0.0 && config.correlation_s > 0.0);
  for (int j = 0; j < config_.count; ++j)
    before_.push_back(
        keptAway(config_.distance_m * Eigen::Vector2d(rng_.gaussian(), rng_.gaussian())));
  after_ = draw();
}

std::vector<Eigen::Vector2d> People::draw() {
  std::vector<Eigen::Vector2d> next;
  const double innovation = std::sqrt(1.0 - a_ * a_) * config_.distance_m;
  for (const Eigen::Vector2d& o : before_)
    next.push_back(
        keptAway(a_ * o + innovation * Eigen::Vector2d(rng_.gaussian(), rng_.gaussian())));
  return next;
}

void People::advanceTo(double t_s) {
  while (double(k_ + 1) * kStepS < t_s) {
    before_ = std::move(after_);
    ++k_;
    after_ = draw();
  }
}

std::optional<double> People::castRay(const Eigen::Vector2d& origin, const Eigen::Vector2d& dir,
                                      const Eigen::Vector2d& robot_world, double t_s,
                                      double max_range_m) {
  if (config_.count == 0) return std::nullopt;
  advanceTo(t_s);
  const double f = std::clamp(t_s / kStepS - double(k_), 0.0, 1.0);
  std::optional<double> nearest;
  for (std::size_t j = 0; j < before_.size(); ++j) {
    const Eigen::Vector2d centre = robot_world + (1.0 - f) * before_[j] + f * after_[j];
    if (const auto s = rayDisc(origin, dir, centre, config_.radius_m);
        s && *s <= max_range_m && (!nearest || *s < *nearest))
      nearest = s;
  }
  return nearest;
}

}  // namespace slamprep::sim
