// checkPathInWorld: the commanded drive, replayed kinematically, must keep the robot's footprint
// in the world's free space (declared in simulator.hpp).

#include <cmath>
#include <sstream>

#include "slamprep/core/error.hpp"
#include "slamprep/sim/drive/controller.hpp"
#include "slamprep/sim/drive/simulator.hpp"

namespace slamprep::sim {
namespace {

std::string formatPoint(const Eigen::Vector2d& p) {
  std::ostringstream out;
  out.precision(3);
  out << std::fixed << "(" << p.x() << ", " << p.y() << ")";
  return out.str();
}

}  // namespace

void checkPathInWorld(const Scene& scene, const Scenario& scenario, const SimConfig& config,
                      const SE2& T_world_start, double duration_s, const HeldSchedule& held) {
  const double radius_m = footprintRadius(config.robot) + config.path_margin_m;
  const std::string world = scene.world().source.string();
  if (scene.collides(T_world_start.translation(), radius_m)) {
    throw InputError(world + ": start",
                     "the robot's footprint (radius " + std::to_string(radius_m) +
                         " m with margin) overlaps static geometry at the start pose " +
                         formatPoint(T_world_start.translation()));
  }
  const Controller controller(scenario.profile, config.nominalGeometry());
  constexpr double kCheckStep_s = 0.01;
  SE2 T_world_base = T_world_start;
  const auto steps = static_cast<std::int64_t>(std::ceil(duration_s / kCheckStep_s));
  for (std::int64_t k = 1; k <= steps; ++k) {
    const double t0 = (k - 1) * kCheckStep_s, t1 = std::min(duration_s, k * kCheckStep_s);
    T_world_base = T_world_base * held.bodyIncrement(controller, config.robot.geometry, t0, t1);
    if (!scene.collides(T_world_base.translation(), radius_m)) continue;
    const ProfileSegment* segment = scenario.profile.segmentAt(t1);
    std::ostringstream what;
    what.precision(2);
    what << std::fixed << "the robot would leave the free space of " << world << " at t = " << t1
         << " s at " << formatPoint(T_world_base.translation()) << " (footprint radius + margin "
         << radius_m << " m): shorten the scenario or pick another world";
    throw InputError(segment != nullptr ? segment->where : scenario.source.string(), what.str());
  }
}

}  // namespace slamprep::sim
