#pragma once
// A dataset directory on disk (docs/dataset.md): what the simulator writes and every
// algorithm reads. Real logs fill the same structure without the ground-truth fields.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/core/diff_drive.hpp"
#include "slamprep/core/laser_scan.hpp"
#include "slamprep/core/samples.hpp"
#include "slamprep/core/time_series.hpp"

namespace slamprep {

/// One lidar scan with what is known about it.
struct ScanRecord {
  LaserScan scan;
  /// True T_world_base at the scan stamp (simulated data only).
  std::optional<SE2> T_world_base_true;
  /// Nominal-odometry T_odom_base at the scan stamp.
  std::optional<SE2> T_odom_base_nominal;
  /// Ground-truth undistorted point of every beam in the lidar frame at the scan stamp
  /// (docs/design.md#what-the-simulators-truth-means); empty without truth, nullopt for no-hit.
  std::vector<std::optional<Eigen::Vector2d>> p_ref_true;
  /// Simulated beams that returned from the world's transients (a twin's replay of its
  /// recording's transient returns, returns that were seen): the dropped-beam fault leaves them.
  /// Empty without any; not written.
  std::vector<std::size_t> replayed_beams;
  /// A de-skewed scan's exact corrected points (lidar frame at the scan stamp), one per measured
  /// beam, nullopt for no return: rays that are not on the scan's regular grid. Empty for a scan
  /// on its grid (docs/dataset.md, "p_ref").
  std::vector<std::optional<Eigen::Vector2d>> p_ref;
};

/// dataset.json: provenance, geometry and sensor configuration.
struct DatasetInfo {
  int format_version = 1;
  std::string world;     ///< world file the data was simulated in ("" for real logs)
  std::string scenario;  ///< scenario file that was driven
  std::uint64_t seed = 0;
  std::optional<DiffDriveParams> true_geometry;  ///< what Bullet simulated; absent for real logs
  DiffDriveParams nominal_geometry;              ///< what the odometry is told
  SE2 T_base_lidar;                              ///< lidar mount ("lidar_mount": x, y, yaw)
  /// The mount that was simulated where the dataset is told another ("true_lidar_mount"; the
  /// simulator's nominal.lidar_mount_error): absent, the told one is the truth.
  std::optional<SE2> true_T_base_lidar;
  int ticks_per_revolution = 4096;
  nlohmann::json config = nlohmann::json::object();  ///< full configuration as simulated
  /// Every injected fault and its events (docs/faults.md); null when none was on.
  nlohmann::json faults;

  /// The mount the lidar really had: what ground truth is measured with.
  const SE2& trueMount() const { return true_T_base_lidar ? *true_T_base_lidar : T_base_lidar; }
};

struct Dataset {
  DatasetInfo info;
  PoseSeries groundtruth;   ///< true T_world_base (groundtruth.tum); empty for real logs
  PoseSeries odom_nominal;  ///< T_odom_base integrated with the nominal geometry (odom_nominal.tum)
  /// The log's own odometry when the encoders are not derived from it (odometry_logged.tum,
  /// optional): a bag's Odometry topic beside its JointState wheel angles. Empty otherwise.
  PoseSeries odometry_logged;
  EncoderLog encoders;            ///< encoders.csv
  ImuLog imu;                     ///< imu.csv
  std::vector<ScanRecord> scans;  ///< scans.jsonl

  bool hasTruth() const { return info.true_geometry.has_value() && !groundtruth.empty(); }
};

}  // namespace slamprep
