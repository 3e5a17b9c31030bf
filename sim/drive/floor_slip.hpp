#pragma once
// Low-friction floor patches (the `floor_patches` fault): which patch each wheel stands on, the
// tyre friction that follows, and the record of every wheel entering or leaving a patch.

#include <array>
#include <nlohmann/json.hpp>
#include <vector>

#include "slamprep/core/se2.hpp"
#include "slamprep/sim/physics/world.hpp"

namespace slamprep::sim {

class FloorSlip {
 public:
  /// half_base_m: the contact points lie at +-half_base_m along the base's y axis.
  FloorSlip(std::vector<FloorPatch> patches, double wheel_friction, double half_base_m);

  /// Tyre friction (left, right) for the base at T_world_base; a change is recorded at t_s.
  /// Bullet combines friction as the product, so a tyre over a patch gets wheel * patch.
  std::array<double, 2> update(double t_s, const SE2& T_world_base);

  /// {"patches": [{"outline", "friction"}], "events": [{"t_s", "wheel", "patch", "entered"}]}.
  nlohmann::json record() const;

 private:
  int patchAt(const Eigen::Vector2d& p_world) const;  // first patch containing p, or -1

  std::vector<FloorPatch> patches_;
  double wheel_friction_;
  double half_base_m_;
  std::array<int, 2> current_{-1, -1};  // (left, right)
  nlohmann::json events_ = nlohmann::json::array();
};

}  // namespace slamprep::sim
