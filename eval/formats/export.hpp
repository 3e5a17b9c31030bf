#pragma once
// Dataset export (docs/export.md): a dataset directory written as a ROS 2 bag (MCAP), a CARMEN
// log, TUM or KITTI trajectories, or CSM laser_data JSON, so other tools open it as it is.

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/core/dataset.hpp"
#include "slamprep/core/enum_names.hpp"
#include "slamprep/eval/formats/compression.hpp"

namespace slamprep::eval {

enum class ExportFormat { kMcap, kCarmen, kTum, kKitti, kCsm };
inline constexpr auto kExportFormatNames = std::to_array<EnumName<ExportFormat>>({
    {ExportFormat::kMcap, "mcap"},
    {ExportFormat::kCarmen, "carmen"},
    {ExportFormat::kTum, "tum"},
    {ExportFormat::kKitti, "kitti"},
    {ExportFormat::kCsm, "csm"},
});

/// A name of kExportFormatNames; throws InputError naming `where` otherwise.
ExportFormat parseExportFormat(const std::string& name, const std::string& where = "--format");

/// The calibrated wheel geometry for the calibrated odometry (the caller chooses it, e.g. the best
/// method of `slamprep calibrate --json`, algo/calibration/calibration_json.hpp).
struct CalibrationChoice {
  DiffDriveParams geometry;
  std::string method;  ///< where it came from, for messages
  /// The calibration's relative_to_odometry: on a log without encoder ticks, the geometry its
  /// wheel increments were derived with (as `calibrate` derived them; unset: dataset.json's).
  std::optional<DiffDriveParams> derived_with;
};

/// Everything an export may write: the dataset plus what later steps left beside it.
struct ExportInput {
  std::string source;  ///< the dataset directory, for messages
  Dataset dataset;
  std::map<std::string, std::vector<ScanRecord>> deskewed;  ///< method -> deskewed_<method>.jsonl
  std::optional<CalibrationChoice> calibration;             ///< none: no calibrated odometry
  std::vector<std::string> notes;  ///< what was found but not used, and why
};

struct ExportParams {
  /// MCAP: messages per chunk of about this many bytes; 0 writes an unchunked file.
  std::size_t mcap_chunk_size_bytes = 1 << 20;
  /// MCAP: chunk compression (zstd, what rosbag2 writes by default).
  Compression mcap_compression = Compression::kZstd;
  /// CARMEN and CSM: which scans to write: "scans" (raw) or a de-skew method name (reads
  /// deskewed_<method>.jsonl).
  std::string scans = "scans";
  /// Frame names used in the MCAP messages (REP 105): world_frame is the ground truth's
  /// (/ground_truth header.frame_id; "map" or "world").
  std::string world_frame = "world";
  std::string odom_frame = "odom";
  std::string base_frame = "base_link";
  std::string laser_frame = "laser";
  /// CARMEN hostname column.
  std::string carmen_hostname = "slamprep";
};

struct ExportResult {
  bool ok = false;
  std::string reason;                         ///< why nothing was written, when !ok
  std::vector<std::filesystem::path> files;   ///< files written
  std::map<std::string, std::size_t> counts;  ///< messages per topic / lines per kind / poses
  std::vector<std::string> notes;             ///< what was left out and why
};

/// Reads the dataset and the de-skewed scans beside it (deskewed_*.jsonl); the calibration is the
/// caller's to fill in.
ExportInput loadExportInput(const std::filesystem::path& dataset_dir);

/// Writes `input` in `format` to `out` (a file for mcap, carmen and csm; a directory for tum and
/// kitti). Every file is written under a temporary name and renamed when complete.
ExportResult exportDataset(const ExportInput& input, ExportFormat format,
                           const std::filesystem::path& out, const ExportParams& params = {});

// The formats as text, for tests and tools.

/// The MCAP file bytes (ros2 profile, CDR messages). Fills `counts` with messages per topic.
std::string formatMcap(const ExportInput& input, const ExportParams& params,
                       std::map<std::string, std::size_t>* counts = nullptr);
/// The same bag written to `file` chunk by chunk as it is made (a temporary sibling, renamed
/// when complete): memory holds the dataset and one chunk, not the bag.
void writeMcapFile(const std::filesystem::path& file, const ExportInput& input,
                   const ExportParams& params, std::map<std::string, std::size_t>* counts);
/// CARMEN log text of `scans` with ODOM lines from the nominal odometry (docs/export.md).
std::string formatCarmen(const Dataset& dataset, const std::vector<ScanRecord>& scans,
                         const ExportParams& params, std::size_t* skipped_scans = nullptr);
/// CSM laser_data JSON lines: CSM's keys only, rays sorted so that theta increases (clockwise
/// scans reversed). A de-skewed scan (ScanRecord::p_ref) is written ray by ray at each corrected
/// point's exact angle and range, not on the grid, cut to one turn (CSM requires max_theta -
/// min_theta <= 2 pi).
std::string formatCsm(const std::vector<ScanRecord>& scans);
/// The sm2 command line for a CSM export: sm2 -in FILE -laser_x X -laser_y Y -laser_theta YAW
/// (the mount in m, m, rad: sm2 turns the base odometry into the first guess with it).
std::string sm2CommandLine(const std::filesystem::path& csm_file, const SE2& T_base_lidar);
/// KITTI poses: one row-major 3x4 [R | t] per line.
std::string formatKittiPoses(const std::vector<SE2>& poses);

/// Body twist (v_x, v_y, w) over the step that ends at sample k: log(T_{k-1}^-1 T_k) / dt
/// (zero at k = 0).
Eigen::Vector3d twistAt(const PoseSeries& poses, std::size_t k);

/// The dataset's odometry re-integrated with the calibration's geometry (wheel_odometry.hpp,
/// the same trajectory as `calibrate --odometry-out`); throws InputError when there is none.
PoseSeries calibratedOdometry(const ExportInput& input);

}  // namespace slamprep::eval
