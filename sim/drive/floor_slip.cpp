#include "slamprep/sim/drive/floor_slip.hpp"

namespace slamprep::sim {

FloorSlip::FloorSlip(std::vector<FloorPatch> patches, double wheel_friction, double half_base_m)
    : patches_(std::move(patches)), wheel_friction_(wheel_friction), half_base_m_(half_base_m) {}

int FloorSlip::patchAt(const Eigen::Vector2d& p_world) const {
  for (std::size_t i = 0; i < patches_.size(); ++i)
    if (insidePolygon(patches_[i].outline_m, p_world)) return static_cast<int>(i);
  return -1;
}

std::array<double, 2> FloorSlip::update(double t_s, const SE2& T_world_base) {
  static constexpr const char* kWheel[2] = {"left", "right"};
  std::array<double, 2> friction{};
  for (int w = 0; w < 2; ++w) {
    const Eigen::Vector2d p_base(0.0, w == 0 ? half_base_m_ : -half_base_m_);
    const int patch = patchAt(T_world_base * p_base);
    if (patch != current_[w]) {
      if (current_[w] >= 0)
        events_.push_back(
            {{"t_s", t_s}, {"wheel", kWheel[w]}, {"patch", current_[w]}, {"entered", false}});
      if (patch >= 0)
        events_.push_back(
            {{"t_s", t_s}, {"wheel", kWheel[w]}, {"patch", patch}, {"entered", true}});
      current_[w] = patch;
    }
    friction[w] = wheel_friction_ * (patch >= 0 ? patches_[patch].friction : 1.0);
  }
  return friction;
}

nlohmann::json FloorSlip::record() const {
  nlohmann::json patches = nlohmann::json::array();
  for (const FloorPatch& p : patches_) {
    nlohmann::json outline = nlohmann::json::array();
    for (const auto& v : p.outline_m) outline.push_back({v.x(), v.y()});
    patches.push_back({{"outline", outline}, {"friction", p.friction}});
  }
  return {{"patches", patches}, {"events", events_}};
}

}  // namespace slamprep::sim
