#pragma once
// A ROS 2 bag on disk: a folder holding metadata.yaml and the storage files it lists (rosbag2
// splits a recording into several .mcap files), or a single .mcap file.

#include <filesystem>
#include <string_view>
#include <vector>

namespace slamprep::eval {

/// The .mcap files of `bag`, in recording order: a folder's metadata.yaml
/// `rosbag2_bagfile_information.relative_file_paths`, or `bag` itself when it is a file. Throws
/// InputError naming the folder or metadata.yaml when the bag is not an MCAP bag (another
/// storage, whole-file compression), a listed file is missing, or the folder has no
/// metadata.yaml.
std::vector<std::filesystem::path> bagFiles(const std::filesystem::path& bag);

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
