#pragma once
// `slamprep twin DATASET --out DIR` (docs/twin.md): a simulation that reproduces a recording.
// The recording's scans matched to a map (slamprep match), the map's walls as a world, the
// matched trajectory as wheel-rate commands, and the lidar, odometry and gyro fitted to what
// the recording shows; every fitted value with how it was measured.

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/core/dataset.hpp"
#include "slamprep/eval/bench/twin_drive.hpp"
#include "slamprep/eval/bench/twin_lidar.hpp"
#include "slamprep/eval/bench/twin_slip.hpp"
#include "slamprep/eval/bench/twin_walls.hpp"
#include "slamprep/sim/drive/config.hpp"
#include "slamprep/sim/drive/scenario.hpp"
#include "slamprep/sim/drive/simulator.hpp"
#include "slamprep/sim/physics/world.hpp"

namespace slamprep::eval {

struct TwinParams {
  std::string deskew = "vicp";  ///< how the scans are matched (slamprep match --deskew)
  WallExtractionParams walls;
  TrackParams track;
  /// The physics' robot follows the drive in closed loop (the scenario's track segment has
  /// closed_loop: true with these gains; its cap is the drive's max_wheel_radps).
  sim::TrackingParams tracking;
  LidarMapParams lidar;
  /// The true geometry of the twin: given (--calibration), else calibrated here (joint, the
  /// scan-to-map motion, 20 cm intervals: results/real's protocol), else the nominal one.
  std::optional<DiffDriveParams> true_geometry;
  bool calibrate = true;
  /// The drive's wheel rates at most this times the recording's 99th percentile (a matching
  /// glitch is not a drive: chasing it would make the twin's robot slip).
  double wheel_rate_margin = 1.25;
  double path_clearance_m = 0.02;  ///< map geometry this close to the robot's path is cut away
  std::uint64_t seed = 1;
};

struct TwinFit {
  sim::World world;
  std::string world_yaml;
  std::string scenario_yaml;
  std::string transients_csv;     ///< the world's transients_file ("": none)
  std::vector<std::string> sets;  ///< `--set key=value`, in order
  sim::SimConfig config;          ///< the defaults with `sets` applied
  nlohmann::ordered_json json;    ///< twin.json without the simulated run's part
  /// The recording's scan-to-map residual (match --deskew none, median over the accepted
  /// scans): what simulateTwin tunes the range noise to.
  double residual_median_m = 0.0;
  /// Its neighbouring beams' residual correlation against its own map (MatchedScans): what
  /// simulateTwin tunes the range noise's correlation along the scan to.
  double residual_neighbour_correlation = 0.0;
  /// Its residual's revisit correlation (MatchedScans): what simulateTwin tunes the share of the
  /// range noise fixed in the world to.
  double residual_revisit_correlation = 0.0;
  /// That share of the range noise's variance (lidar.range_noise_fixed_m; the rest drawn afresh
  /// each scan): first the recording's revisit correlation, then tuned.
  double range_noise_fixed_share = 0.0;
  LidarLayout layout;          ///< the recording's lidar
  WallExtractionParams walls;  ///< how its map was made into walls
  LidarMapParams lidar;        ///< how its scans were compared with them
  /// The kinematic robot's path at the knots (scenario time): what the physics must follow.
  PoseSeries replay;
  /// The physics' robot farther than this from `replay` although driven in closed loop (a wall
  /// touched, a turn the capped wheels cannot follow): the twin is simulated in kinematic mode
  /// instead.
  double max_physics_deviation_m = 0.3;
  std::string deskew;  ///< how the scans were matched for the map and the slip (TwinParams)
  /// The random wheel slip the recording shows (its wheels with the true geometry against its
  /// scans matched alone), and what it was fitted on: simulateTwin gives the twin what its run
  /// without slip at the tuned range noise, measured the same way, does not show already, the
  /// recording fitted again with its reference noise held at that run's where the run's is less.
  WheelSlipFit recording_slip;
  WheelSlipInput recording_slip_input;
};

/// Simulates the twin, in physics mode when its robot follows the replay within
/// max_physics_deviation_m, else in kinematic mode (twin.json drive.mode says which and why).
/// The range noise is tuned first, without slip: the point-to-line residual grows about in
/// proportion to it, so one run at the fitted noise and one secant step make the twin's
/// residual the recording's (twin.json "range_noise_m" says what each run measured). The last
/// of those runs measures the slip the twin lacks; given some, the twin is one more run.
sim::SimResult simulateTwin(TwinFit& fit, const sim::Scenario& scenario);

/// Fits the twin of `real` (named `name` in the output). Throws InputError when the dataset
/// cannot be matched (fewer than two scans, no accepted match).
TwinFit fitTwin(const Dataset& real, const std::string& name, const TwinParams& params = {});

/// The world as a world file (docs/worlds.md); the walls keep their faces where the returns lay.
std::string worldYaml(const sim::World& world, const std::string& comment);

/// The drive as a scenario file with one `track` segment of wheel rates (docs/simulate.md),
/// driven in closed loop with `tracking`'s gains and `track`'s wheel-rate cap.
std::string scenarioYaml(const TrackedDrive& drive, const TrackParams& track,
                         const sim::TrackingParams& tracking, const std::string& comment);

}  // namespace slamprep::eval
