#pragma once
// Importing real logs into a dataset directory (docs/export.md, "Import"): a CARMEN log, or a
// ROS 2 bag (a folder with metadata.yaml and split sqlite3 .db3 or .mcap files, maybe zstd
// compressed per file or per message, or one .db3 or .mcap file; CDR) with
// sensor_msgs/LaserScan plus nav_msgs/Odometry or sensor_msgs/JointState. The result has no
// ground truth; calibrate and deskew read it.

#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/core/dataset.hpp"
#include "slamprep/eval/formats/range_limit.hpp"
#include "slamprep/eval/formats/stale_odometry.hpp"
#include "slamprep/eval/formats/twist_spikes.hpp"

namespace slamprep::eval {

struct ImportParams {
  /// Wheel geometry written as the nominal one; encoders derived from odometry poses use it, so
  /// re-integrating them reproduces the logged odometry whatever the values, but calibration
  /// results are relative to it: give the geometry the robot's odometry was configured with.
  /// nullopt: the log's (CARMEN `PARAM slamprep_nominal_*` lines; CARMEN without either: no
  /// encoders are derived, a CARMEN log has odometry poses, not wheel ticks; MCAP: slamprep's
  /// Metadata record, else the import is refused: it is never guessed).
  std::optional<DiffDriveParams> nominal_geometry;
  /// Resolution of derived encoder ticks (from poses or joint angles): 2^20 per revolution
  /// keeps the rounding below 6e-6 rad per sample.
  int ticks_per_revolution = 1 << 20;
  /// Time between beams for logs that do not carry it (CARMEN); nullopt: the log's
  /// `PARAM slamprep_time_increment`, else 0 = unknown (de-skew refuses such scans). MCAP: given,
  /// it replaces every LaserScan's; otherwise the messages keep their own (0 kept, with a note).
  std::optional<double> time_increment_s;
  /// Bags (`--time-increment auto`): a scan whose time_increment is 0 is given that of a head that
  /// turns once per scan, the scans' median period times |angle_increment| / 2 pi; scans that
  /// carry one keep it. Not with time_increment_s.
  bool time_increment_one_turn = false;
  /// Lidar mount; nullopt: from the log (CARMEN `PARAM robot_frontlaser_offset` and its
  /// side/angular offsets, rear laser: `robot_rearlaser_offset` turned by pi; MCAP: the tf tree of
  /// /tf_static and /tf from base_frame to the scans' frame), identity when the log has none.
  std::optional<SE2> T_base_lidar;
  /// CARMEN: take the mount from the laser lines' robot_pose^-1 laser_pose (first line) when
  /// neither T_base_lidar nor a PARAM gives it, even where the lines' offsets differ (by default
  /// only one offset shared by every line is taken: two pose estimates are not a calibration).
  bool lidar_mount_from_poses = false;
  /// CARMEN: stamps running backwards within a stream by up to this much are sorted into
  /// place (or, with drop_late_stamps, the late lines dropped); larger backward steps are refused.
  double reorder_tolerance_s = 0.05;
  /// CARMEN: drop the lines stamped at or after a later line of their stream instead of sorting
  /// (for logs whose lines are in order but some stamps late, as the Intel log).
  bool drop_late_stamps = false;
  /// CARMEN laser message to import (ROBOTLASER1, FLASER, RLASER, RAWLASER1..4); empty = the
  /// first of that list the log has.
  std::string laser;
  /// CARMEN odometry: "odom" (ODOM lines), "laser" (the imported laser lines' robot poses) or
  /// "" = ODOM lines when the log has at least 2, else the laser lines.
  std::string odometry;
  /// MCAP: the robot's base frame in the tf tree.
  std::string base_frame = "base_link";
  /// Drop the scans that the odometry does not cover (before its first sample or after its last,
  /// as topics start and stop at different times) instead of refusing the log (--no-trim).
  bool trim = true;
  /// MCAP topics; empty = the only channel of that message type (or /scan, /odom,
  /// /joint_states, /imu when there are several).
  std::string scan_topic, odom_topic, joint_topic, imu_topic;
  /// JointState names of the wheels; empty = the one joint whose name contains "left"/"right".
  std::string left_joint, right_joint;
  /// Readings beyond this become "no return" and every scan's range_max is set to it; nullopt:
  /// the scans' own range_max (a note when it exceeds twice the 99.9th percentile of the
  /// readings, range_limit.hpp).
  std::optional<double> max_range_m;
  /// The beams were taken in the reverse of their array order: an RPLIDAR turns clockwise and
  /// its ROS driver publishes the beams counter-clockwise, yet with a positive time_increment.
  /// Each scan is reversed so that the array runs in time order (angle_increment negated), the
  /// stamp staying the first measured beam's. Check with `match --deskew` on a turning log: de-
  /// skew that raises the residual in turns points to this (docs/export.md).
  bool reverse_beam_time = false;
  /// MCAP: park the scans in a file in this directory while the bag is read, and hand them out
  /// through ImportResult::scans instead of Dataset::scans (memory then holds the other streams
  /// and one chunk; `slamprep import` spills into the dataset directory it is writing). Empty:
  /// the scans are held in memory.
  std::filesystem::path spill_dir;
};

/// What an import read and decided, printed by `slamprep import` and written by its --json.
struct ImportSummary {
  std::string storage;  ///< bags: storage, files, metadata.yaml version, compression
  std::map<std::string, std::string> topics;  ///< bags: message type -> topic read
  std::string scans;                          ///< which lines or messages, beams and angles
  std::string odometry;                       ///< ODOM lines, laser poses, Odometry or JointState
  std::string lidar_mount;                    ///< value and where it came from
  std::string nominal_geometry;      ///< value and where it came from, or why there is none
  std::string time_increment;        ///< value and where it came from
  std::optional<RangeReport> range;  ///< the maximum range rule (range_limit.hpp)
  std::vector<StaleReport> stale;    ///< per odometry stream checked
  std::optional<TwistSpikeReport> twist_spikes;  ///< bags with Odometry
  std::map<std::string, std::size_t> reordered;  ///< CARMEN: message -> lines sorted into place
  std::map<std::string, std::size_t> dropped;    ///< CARMEN: reason -> lines not imported
};

/// The scans of an import that spilled them (ImportParams::spill_dir), in stamp order, ready to
/// be written: mount, time increment and odometry pose applied as the in-memory import applies
/// them; a scan the odometry does not cover is dropped (ImportParams::trim), else next() throws.
class ScanStream {
 public:
  virtual ~ScanStream() = default;
  /// The next scan; false after the last.
  virtual bool next(ScanRecord& out) = 0;
  /// Scans handed out so far.
  virtual std::size_t count() const = 0;
  /// Notes on the scans (time increments replaced or 0, scans dropped), once all were read.
  virtual std::vector<std::string> notes() const = 0;
};

struct ImportResult {
  Dataset dataset;                 ///< without scans when `scans` is set
  std::vector<std::string> notes;  ///< what was assumed or dropped, for the user
  ImportSummary summary;
  std::unique_ptr<ScanStream> scans;  ///< set when the scans were spilled
};

/// Throws InputError naming the file, line and field on malformed logs, stamps out of order
/// beyond params.reorder_tolerance_s, logs without laser lines or odometry (ODOM or laser
/// poses), and scans the odometry does not cover (unless params.trim).
ImportResult importCarmen(std::string_view text, const std::string& file,
                          const ImportParams& params = {});

/// A ROS 2 bag: a folder (metadata.yaml, its storage files in order: sqlite3 or MCAP, FILE or
/// MESSAGE zstd compression) or one .db3 or .mcap file, read message by message (never whole;
/// FILE-compressed files are unpacked into a scratch folder under spill_dir or the system temp,
/// removed afterwards). Throws InputError naming the file, byte offset or row, topic and field
/// on malformed storage or CDR, missing topics, non-finite values, empty scans, unsorted or
/// duplicate stamps, a tilted lidar, or no nominal geometry.
ImportResult importRosbag2(const std::filesystem::path& bag, const ImportParams& params = {});
/// The same (`--format mcap`, kept for scripts: any rosbag2 storage is read).
ImportResult importMcap(const std::filesystem::path& bag, const ImportParams& params = {});
/// The same for one MCAP file held in memory (`file` names it in errors).
ImportResult importMcap(std::string_view bytes, const std::string& file,
                        const ImportParams& params = {});

/// Encoder ticks that reproduce `poses` (T_odom_base) under `geometry`: each step's arc
/// log(T_{k-1}^-1 T_k) = (s, lateral, dth) gives the wheel turns
/// dphi_L = (s - dth b/2) / r_L, dphi_R = (s + dth b/2) / r_R (inverse of the arc model of
/// wheelIncrement). `max_lateral_m` receives the largest lateral step, which no wheel motion
/// explains and which is dropped.
EncoderLog encodersFromPoses(const PoseSeries& poses, const DiffDriveParams& geometry,
                             int ticks_per_revolution, double* max_lateral_m = nullptr);

}  // namespace slamprep::eval
