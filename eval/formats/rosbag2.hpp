#pragma once
// A ROS 2 bag on disk: a folder holding metadata.yaml and the storage files it lists (rosbag2
// splits a recording into several files, sqlite3 .db3 or .mcap, each possibly compressed whole
// with zstd), or a single .db3 or .mcap file.

#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/core/enum_names.hpp"

namespace slamprep::eval {

enum class BagStorageKind { kMcap, kSqlite3 };
enum class BagCompressionMode { kNone, kFile, kMessage };
/// metadata.yaml's storage_identifier and compression_mode values.
inline constexpr auto kBagStorageNames = std::to_array<EnumName<BagStorageKind>>({
    {BagStorageKind::kSqlite3, "sqlite3"},
    {BagStorageKind::kMcap, "mcap"},
});
inline constexpr auto kBagCompressionModeNames = std::to_array<EnumName<BagCompressionMode>>({
    {BagCompressionMode::kNone, "NONE"},
    {BagCompressionMode::kFile, "FILE"},
    {BagCompressionMode::kMessage, "MESSAGE"},
});

/// What metadata.yaml `rosbag2_bagfile_information` says (or, for one file, its magic).
struct Rosbag2Bag {
  std::filesystem::path path;  ///< the folder or the file given
  int version = 0;             ///< metadata.yaml version; 0 without one
  BagStorageKind storage = BagStorageKind::kMcap;
  std::string storage_identifier;  ///< "mcap" or "sqlite3"
  BagCompressionMode compression = BagCompressionMode::kNone;
  std::string compression_format;            ///< "" or "zstd"
  std::vector<std::filesystem::path> files;  ///< the storage files, in recording order
  std::vector<std::string> notes;            ///< what reading them assumed (a renamed bag)
};

/// Reads a bag folder's metadata.yaml (versions 1 to 9 as rosbag2 writes them: only
/// storage_identifier, relative_file_paths, compression_format and compression_mode are used;
/// topics, QoS strings or lists, type hashes and custom data are ignored), or takes one storage
/// file by its magic (SQLite, MCAP, a zstd frame: a FILE-compressed storage file) or extension.
/// A renamed bag (no listed file present, the folder holding as many storage files of one kind
/// as are listed) is read from the files it holds, in split order (_2 before _10), with a note. Throws InputError
/// naming the folder, metadata.yaml or file when there is no metadata.yaml, a listed file is
/// missing otherwise, or the storage or compression is unknown.
Rosbag2Bag readRosbag2(const std::filesystem::path& bag);

std::string_view storageName(BagStorageKind k);
std::string_view compressionModeName(BagCompressionMode m);

/// The MCAP Metadata record in which slamprep's export keeps what a bag cannot otherwise say:
/// the nominal wheel geometry (keys below, metres, as decimal text), and "odometry_heading":
/// "gyro" when the Odometry's heading is the integrated gyro, not the wheels' (absent
/// otherwise): its poses are then not the JointState ticks integrated.
inline constexpr std::string_view kSlamprepMetadata = "slamprep";
inline constexpr std::string_view kNominalRadiusLeft = "nominal_wheel_radius_left_m";
inline constexpr std::string_view kNominalRadiusRight = "nominal_wheel_radius_right_m";
inline constexpr std::string_view kNominalWheelBase = "nominal_wheel_base_m";
inline constexpr std::string_view kOdometryHeading = "odometry_heading";

}  // namespace slamprep::eval
