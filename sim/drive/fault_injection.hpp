#pragma once
// Injects the sensor-stream faults (everything but floor patches, glass and the held robot, which
// act inside the physics and the ray caster) into simulated logs, and records every event it
// injects.

#include <cstdint>
#include <nlohmann/json.hpp>

#include "slamprep/core/dataset.hpp"
#include "slamprep/sim/drive/config.hpp"
#include "slamprep/sim/drive/faults.hpp"
#include "slamprep/sim/drive/floor_slip.hpp"
#include "slamprep/sim/drive/held_robot.hpp"
#include "slamprep/sim/physics/world.hpp"

namespace slamprep::sim {

/// Nominal sample rates: jitter is cut at 0.45 periods so stamps stay in order.
struct StreamRates {
  double encoders_hz = 100.0;
  double imu_hz = 200.0;
  double lidar_hz = 10.0;
};

/// Applies the enabled stream faults to data.encoders, data.imu and data.scans in place (before
/// the odometry is integrated) and returns their record for dataset.json's "faults" (without
/// "enabled"; docs/faults.md). Each fault draws from its own stream of `seed`, indexed by the
/// sample's place in the clean log, so its events do not depend on which other faults are on.
nlohmann::json injectStreamFaults(const FaultsConfig& faults, std::uint64_t seed,
                                  const StreamRates& rates, double duration_s, Dataset& data);

/// The world as the faults that are on make it: unless `glass` is on, `returns: false` objects
/// return like any other; unless `floor_patches` is on, the floor is uniform.
World worldWithFaults(const World& world, const FaultSet& faults);

/// Injects the stream faults of config.faults into `data` and returns dataset.json's "faults":
/// {"enabled": [...], "<fault>": its record, ...}. `slip` is the floor-patch tracker of the run
/// (null in kinematic mode or with floor_patches off), `held` the run's held windows.
nlohmann::json injectFaults(const SimConfig& config, const World& world, const FloorSlip* slip,
                            const HeldSchedule& held, double duration_s, Dataset& data);

}  // namespace slamprep::sim
