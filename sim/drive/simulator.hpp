#pragma once
// The simulation loop: drives the robot through a scenario in a world (Bullet physics, or exact
// kinematics), streams every sensor at its own rate, and fills a Dataset with ground truth.

#include <functional>

#include "slamprep/core/dataset.hpp"
#include "slamprep/eval/metrics/odometry_drift.hpp"
#include "slamprep/sim/drive/config.hpp"
#include "slamprep/sim/drive/held_robot.hpp"
#include "slamprep/sim/drive/scenario.hpp"
#include "slamprep/sim/physics/scene.hpp"
#include "slamprep/sim/physics/world.hpp"

namespace slamprep::sim {

/// Called now and then with the simulated time so far and the total.
using ProgressCallback = std::function<void(double sim_time_s, double duration_s)>;

struct SimSummary {
  SimMode mode = SimMode::physics;
  double duration_s = 0.0;        ///< simulated time
  std::size_t physics_steps = 0;  ///< fixed steps taken
  std::size_t scans = 0;          ///< complete scans
  std::size_t beams = 0;          ///< beams cast in complete scans
  std::size_t returns = 0;        ///< beams with a valid range
  double distance_m = 0.0;        ///< length of the true path
  double rotation_rad = 0.0;      ///< total |yaw| turned
  /// Dead reckoning against the truth, both from their first common pose (eval::odometryDrift):
  eval::DriftResult drift_nominal;  ///< encoders integrated with the NOMINAL geometry
  eval::DriftResult drift_true;     ///< ... with the TRUE geometry (slip + ticks); when known
};

struct SimResult {
  Dataset dataset;
  SimSummary summary;
};

/// Loads config.world and config.scenario (resolveDataPath) and simulates. Throws InputError on
/// bad configuration, bad files, or a scenario that leaves the world's free space.
SimResult simulate(const SimConfig& config, const ProgressCallback& progress = {});

/// Simulates an already loaded world and scenario (tests build them in memory); `explore`
/// segments are planned in the world first (planExplore). `physics` sets
/// Bullet's solver (config.solver_iterations, when > 0, overrides its iterations).
SimResult simulate(const SimConfig& config, const World& world, const Scenario& scenario,
                   const ProgressCallback& progress = {}, ScenePhysicsParams physics = {});

/// Drives the commanded profile kinematically with the true geometry (the path the robot will
/// take, up to slip; standing still while `held`) from `T_world_start` and checks every 10 ms
/// that the footprint plus margin stays clear of static geometry. Throws InputError naming the
/// scenario segment otherwise.
void checkPathInWorld(const Scene& scene, const Scenario& scenario, const SimConfig& config,
                      const SE2& T_world_start, double duration_s,
                      const HeldSchedule& held = HeldSchedule());

/// Statistics of a simulated dataset: counts, distance, and odometry drift with both geometries.
SimSummary summarize(const Dataset& dataset, SimMode mode);

}  // namespace slamprep::sim
