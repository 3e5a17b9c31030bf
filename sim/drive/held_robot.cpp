#include "slamprep/sim/drive/held_robot.hpp"

#include <algorithm>

#include "slamprep/core/odometry.hpp"

namespace slamprep::sim {

HeldSchedule::HeldSchedule(const FaultsConfig& f, std::uint64_t seed, double duration_s) {
  SplitMix64 rng(streamSeed(seed, RngStream::fault_held_robot));
  windows_ = poissonWindows(rng, f.held_robot_rate_hz, f.held_robot_min_duration_s,
                            f.held_robot_max_duration_s, duration_s);
}

bool HeldSchedule::heldAt(double t_s) const {
  return std::any_of(windows_.begin(), windows_.end(),
                     [t_s](const TimeWindow& w) { return w.contains(t_s); });
}

SE2 HeldSchedule::bodyIncrement(const Controller& controller, const DiffDriveParams& geometry,
                                double t0_s, double t1_s) const {
  const auto arc = [&](double a, double b) {
    const Eigen::Vector2d dphi = controller.wheelAngleIncrement(a, b);
    return wheelIncrement(geometry, dphi.x(), dphi.y());
  };
  SE2 T;
  double free_from = t0_s;  // start of the part not yet integrated
  bool split = false;
  for (const TimeWindow& w : windows_) {
    if (w.to_s <= free_from || w.from_s >= t1_s) continue;
    if (w.from_s > free_from) T = T * arc(free_from, w.from_s);
    free_from = std::min(t1_s, w.to_s);
    split = true;
  }
  if (!split) return arc(t0_s, t1_s);  // the usual step: exactly as without the fault
  if (free_from < t1_s) T = T * arc(free_from, t1_s);
  return T;
}

nlohmann::json HeldSchedule::record(const FaultsConfig& f) const {
  nlohmann::json events = nlohmann::json::array();
  for (const TimeWindow& w : windows_)
    events.push_back({{"t_from_s", w.from_s}, {"t_to_s", w.to_s}});
  return {{"rate_hz", f.held_robot_rate_hz},
          {"min_duration_s", f.held_robot_min_duration_s},
          {"max_duration_s", f.held_robot_max_duration_s},
          {"events", events}};
}

}  // namespace slamprep::sim
