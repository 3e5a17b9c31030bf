#pragma once
// TUM trajectory files: one pose per line "t x y z qx qy qz qw", '#' comments (docs/dataset.md).
// Planar poses are written with z = 0 and the quaternion of the yaw, chosen so that the reader
// recovers the yaw bit for bit.

#include <filesystem>
#include <string>
#include <string_view>

#include "slamprep/core/time_series.hpp"

namespace slamprep::eval {

/// The unit quaternion (0, 0, qz, qw) of a rotation by yaw about z, nudged by a few ulps so that
/// yawFromQuaternion(0, 0, qz, qw) == yaw_rad exactly (for normal, non-subnormal yaw).
struct YawQuaternion {
  double qz = 0.0;
  double qw = 1.0;
};
YawQuaternion yawToQuaternion(double yaw_rad);

/// Yaw (rad, wrapped to (-pi, pi]) of a quaternion about any axis: the heading of its x axis
/// projected on the plane. Scale invariant (the quaternion need not be exactly unit).
double yawFromQuaternion(double qx, double qy, double qz, double qw);

/// TUM text of a planar trajectory, with a '#' header line. Throws InputError("file:line") for
/// non-finite values or stamps that do not increase (what the reader would reject).
std::string formatTum(const PoseSeries& poses, const std::string& file);
/// The same text written to `path` piece by piece.
void writeTum(const std::filesystem::path& path, const PoseSeries& poses, const std::string& file);
/// Parses TUM text; `file` names it in errors. Rejects wrong column counts, non-numbers, NaN/Inf,
/// quaternions far from unit norm and timestamps that do not increase strictly.
PoseSeries parseTum(std::string_view text, const std::string& file);

PoseSeries readTum(const std::filesystem::path& path);

}  // namespace slamprep::eval
