#pragma once
// The simulation loop: drives the robot through a scenario in a world (Bullet physics, or exact
// kinematics), streams every sensor at its own rate, and fills a Dataset with ground truth.

#include <functional>
#include <string>
#include <vector>

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

/// The robot's true state at the end of a physics step: what every sensor reads.
struct MotionState {
  double t_s = 0.0;
  SE2 T_world_base;
  Eigen::Vector2d wheel_angle_rad = Eigen::Vector2d::Zero();  ///< (left, right) since start
  Eigen::Vector2d v_world_mps = Eigen::Vector2d::Zero();      ///< base origin velocity
  double yaw_rate_radps = 0.0;
};

/// A run's true motion, kept for a later run that changes only what its sensors do: a twin's
/// tuning runs change the lidar's noise, then the encoders' slip, and would otherwise step the
/// same physics again (docs/simulate.md, "A motion replayed").
struct RecordedMotion {
  std::string key;                  ///< motionKey() of the run that recorded it ("": none)
  std::vector<MotionState> states;  ///< at t = 0 and after every physics step
};

/// What of `config` the motion depends on, as text: all of it but the lidar, the encoders, the
/// IMU, the published odometry's heading and the faults that act on them only. Two
/// configurations with the same key drive the robot the same way, step for step, in the same
/// world and scenario.
std::string motionKey(const SimConfig& config);

/// simulate, with the motion replayed from `motion` where it was recorded under this
/// configuration's motionKey, else stepped and recorded there. The world, the scenario and the
/// physics parameters must be the recording run's (the caller's to keep). Runs with the
/// floor_patches fault are neither replayed nor recorded (their patches' state is the physics').
SimResult simulate(const SimConfig& config, const World& world, const Scenario& scenario,
                   RecordedMotion& motion, const ProgressCallback& progress = {},
                   ScenePhysicsParams physics = {});

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
