#pragma once
// The simulator's whole configuration: one struct with defaults, `key=value` overrides by dotted
// key (docs/simulate.md lists every key), and JSON for dataset.json's "config" field.

#include <cstdint>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slamprep/core/diff_drive.hpp"
#include "slamprep/core/enum_names.hpp"
#include "slamprep/sim/drive/faults.hpp"
#include "slamprep/sim/drive/people.hpp"
#include "slamprep/sim/drive/sensors.hpp"
#include "slamprep/sim/physics/lidar.hpp"
#include "slamprep/sim/physics/robot.hpp"

namespace slamprep::sim {

/// physics: Bullet rigid bodies, motors and contacts. kinematic: no physics; the true pose is the
/// exact integration of the commanded wheel rates with the true geometry.
enum class SimMode { physics, kinematic };
/// As the `mode` key, --mode and suites spell them.
inline constexpr auto kSimModeNames = std::to_array<EnumName<SimMode>>({
    {SimMode::physics, "physics"},
    {SimMode::kinematic, "kinematic"},
});

/// How wrong the odometry's geometry is: nominal = true * (1 + error).
struct NominalErrors {
  double radius_left_error = 0.02;     ///< r_L: +2 %
  double radius_right_error = -0.015;  ///< r_R: -1.5 %
  double wheel_base_error = 0.04;      ///< b: +4 %
  /// The lidar mount the dataset is told: the true one plus these (0: the truth is told).
  double lidar_mount_x_error_m = 0.0;
  double lidar_mount_y_error_m = 0.0;
  double lidar_mount_yaw_error_rad = 0.0;
  bool mountToldWrong() const {
    return lidar_mount_x_error_m != 0.0 || lidar_mount_y_error_m != 0.0 ||
           lidar_mount_yaw_error_rad != 0.0;
  }
};

/// Where the robot starts, moved per seed: uniform offsets of up to +-position_m in x and y and
/// +-yaw_deg in heading from the world's start pose, drawn from the seed's own stream. 0 (the
/// default) starts every seed at the world's start pose. Repeated runs then differ in where the
/// robot drives relative to the walls, as repeated real experiments do.
struct StartJitter {
  double position_m = 0.0;
  double yaw_deg = 0.0;
  bool any() const { return position_m > 0.0 || yaw_deg > 0.0; }
};

/// Where the published odometry (odom_nominal) takes its heading from: the wheels (their
/// rotation difference over the nominal wheel base) or the integrated gyro, as TurtleBot3's
/// turtlebot3_node does with use_imu. The translation is the wheels' either way.
enum class OdometryHeading { wheels, gyro };
inline constexpr auto kOdometryHeadingNames = std::to_array<EnumName<OdometryHeading>>({
    {OdometryHeading::wheels, "wheels"},
    {OdometryHeading::gyro, "gyro"},
});

struct OdometryConfig {
  OdometryHeading heading_from = OdometryHeading::wheels;  ///< odometry.heading_from
};

struct SimConfig {
  std::string world = "worlds/room.yaml";  ///< world file (relative: cwd, then dataDir())
  std::string scenario = "worlds/scenarios/default.yaml";  ///< scenario file (same lookup)
  double duration_s = 0.0;          ///< simulated time; 0 = the scenario's own length
  std::uint64_t seed = 1;           ///< seeds every sensor's noise stream
  SimMode mode = SimMode::physics;  ///< physics or kinematic
  double physics_rate_hz = 1000.0;  ///< fixed physics (and ground-truth) step rate
  int solver_iterations = 0;        ///< Bullet constraint-solver iterations; 0 keeps the Scene's
  double path_margin_m = 0.05;      ///< clearance the pre-check demands around the footprint
  StartJitter start_jitter;         ///< per-seed start pose offsets, off by default
  RobotConfig robot;                ///< TRUE geometry and the physical robot
  NominalErrors nominal;            ///< what the odometry (and the controller) believe
  LidarConfig lidar;                ///< rotating lidar
  EncoderConfig encoders;           ///< wheel encoders
  ImuConfig imu;                    ///< planar IMU
  OdometryConfig odometry;          ///< how odom_nominal is integrated
  FaultsConfig faults;              ///< injected faults, all off by default (docs/faults.md)
  PeopleConfig people;              ///< people about the robot, none by default

  /// The geometry the odometry is told: the true geometry scaled by the nominal errors.
  DiffDriveParams nominalGeometry() const;
  /// The lidar mount the dataset is told (dataset.json "lidar_mount"): the true one moved by
  /// nominal.lidar_mount_error.
  SE2 nominalMount() const;
  /// The world's start pose moved by this seed's start_jitter draw (unchanged when it is off).
  SE2 startPose(const SE2& T_world_start) const;
};

/// Every configuration key, dotted ("lidar.rate_hz"), in a fixed order.
std::vector<std::string> configKeys();

/// The configuration as nested JSON ({"lidar": {"rate_hz": 10, ...}, ...}). The "faults" keys
/// appear only when a fault is on, "odometry" only when its heading is the gyro's (or when
/// every_key is set), so configurations without them read as they did before they existed.
nlohmann::json toJson(const SimConfig& config, bool every_key = false);

/// Reads a configuration written by toJson; missing keys keep their defaults. Throws InputError
/// naming `where` and the key for unknown keys and wrong types, and validates the result.
SimConfig configFromJson(const nlohmann::json& json, const std::string& where);

/// Applies one "key=value" override. Throws InputError("--set key", ...) for an unknown key, a
/// value of the wrong type, or a value that makes the configuration invalid.
void applyOverride(SimConfig& config, const std::string& assignment);

/// Sensor rates beyond any real sensor (docs/simulate.md, "Limits").
inline constexpr double kMaxLidarRate_hz = 100.0;
inline constexpr double kMaxSensorRate_hz = 10000.0;  ///< encoders and IMU
inline constexpr double kMaxFaultRate_hz = 100.0;     ///< events of one fault per second
inline constexpr double kMaxSlipSigma = 0.5;  ///< encoders.slip_sigma, encoders.turn_slip_sigma
/// Samples of one run: physics steps, encoder and IMU samples each (a day at 1 kHz is 8.6e7),
/// and lidar beams (a day at 10 Hz x 720 beams is 6.2e8); more cannot be held in memory.
inline constexpr double kMaxSamples = 1e8;
inline constexpr double kMaxBeams = 1e9;

/// Checks ranges (positive radii, at least one beam, ...). Throws InputError("where: key", ...).
void validate(const SimConfig& config, const std::string& where);

/// Refuses a run of `duration_s` whose streams would exceed kMaxSamples or kMaxBeams, naming the
/// rate keys, before anything is simulated. Throws InputError.
void checkRunSize(const SimConfig& config, double duration_s);

/// Robot footprint: radius of the smallest circle about the base origin containing the chassis,
/// wheels and casters.
double footprintRadius(const RobotConfig& robot);

}  // namespace slamprep::sim
