#pragma once
// What the CARMEN and bag importers (import_carmen.cpp, import_bag.cpp) share: parameter
// checks, attaching the odometry to the scans, the dataset info of an import, wheel ticks.

#include <cstdint>
#include <string>
#include <vector>

#include "slamprep/core/dataset.hpp"
#include "slamprep/eval/formats/import.hpp"

namespace slamprep::eval {

/// Throws InputError(where, ...) unless both wheel radii and the wheel base are finite and > 0.
void checkGeometry(const DiffDriveParams& g, const std::string& where);

/// Throws InputError naming the command-line option of the first invalid parameter.
void checkParams(const ImportParams& p);

/// Attaches the odometry pose at its stamp to one scan; false when the odometry does not cover
/// the scan and `trim` says drop it; without trim such a scan is refused (InputError at `where`).
bool attachOdometryTo(ScanRecord& scan, const PoseSeries& odometry, bool trim,
                      const std::string& where);

/// "N scans outside the odometry ... were dropped (--trim, ...)"; empty when none was.
std::string trimmedNote(std::size_t dropped);

/// Attaches the odometry to the scans; refuses (or with trim drops) scans it does not cover.
void attachOdometry(Dataset& d, bool trim, const std::vector<std::string>& scan_where,
                    std::vector<std::string>& notes);

/// The info of an imported dataset: the nominal geometry, the tick resolution and where it came
/// from (file, format, what the encoders were derived from: `encoders` in words,
/// `encoders_from` the structured key "joint_states" | "odometry_poses", empty: no encoders).
DatasetInfo importedInfo(const ImportParams& p, const DiffDriveParams& nominal,
                         const std::string& file, const char* format, const std::string& encoders,
                         const std::string& encoders_from);

/// The wheel angle as a whole number of ticks; throws InputError(where, ...) when out of range.
std::int64_t ticksOf(double angle_rad, double rad_per_tick, const std::string& where);

}  // namespace slamprep::eval
