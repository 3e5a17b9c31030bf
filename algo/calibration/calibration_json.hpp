#pragma once
// The calibration JSON (`slamprep calibrate --json`, docs/calibration.md): written and read here
// only. An array, one object per method run: "method", "ok", "reason", "r_L", "r_R", "b", and
// for joint and ceres "lidar_x", "lidar_y", "lidar_yaw" (metres, radians; null when not ok),
// "sigma" (same keys), "error" (estimate minus truth, when there is truth), "condition_number",
// "intervals", "intervals_trimmed", "trimmed_worst" ([{"t0", "t1", "reason", "residual"}], the
// robust screening's worst outliers), and for a log without encoder ticks
// "relative_to_odometry" (the nominal r_L, r_R, b the wheel increments were derived with),
// "scale" (estimate / nominal, when ok) and "meaning" (a sentence saying so).

#include <Eigen/Core>
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/algo/calibration/calibrate.hpp"
#include "slamprep/algo/calibration/calibration_report.hpp"
#include "slamprep/core/diff_drive.hpp"
#include "slamprep/core/se2.hpp"

namespace slamprep::algo {

/// estimate(i) - truth(i), the yaw (i = 5) wrapped to (-pi, pi].
double calibrationError(const Eigen::VectorXd& estimate, const Eigen::VectorXd& truth, int i);

/// The sentence "meaning" holds for results relative to a log's odometry geometry `nominal`.
std::string odometryRelativeMeaning(const DiffDriveParams& nominal);

/// The JSON text of `calibrate --json` (two-space indent, keys sorted, newline at the end): with
/// one recording the array of its method objects; with several
/// {"recordings": [{"dataset", "methods": [...]}], "combined": [...], "consistency":
/// {METHOD: {PARAM: {"chi2_dof", "n"}}}}. Every method object is written by one function:
/// today's keys, plus "flags" when there are any, "validation" when there is one and
/// "against_nominal" where the method is ok and the recording has a nominal geometry.
std::string formatCalibrateJson(const CalibrateReport& report);
/// The array of method objects of bare runs (no flags, no validation).
std::string formatCalibrationJson(const std::vector<CalibrationRun>& runs,
                                  const std::optional<CalibrationTruth>& truth);
/// Writes formatCalibrationJson to `path` (atomically). InputError when it cannot.
void writeCalibrationJson(const std::filesystem::path& path,
                          const std::vector<CalibrationRun>& runs,
                          const std::optional<CalibrationTruth>& truth);
/// Writes formatCalibrateJson to `path` (atomically).
void writeCalibrateJson(const std::filesystem::path& path, const CalibrateReport& report);

/// A calibration JSON as read back: every run in file order, and the best one.
struct CalibrationFile {
  std::string source;  ///< the file (or what the text came from), for messages
  /// Each entry's method, ok, reason, intervals_trimmed, trimmed_worst, relative_to_odometry
  /// and, when ok, geometry (and mount for joint and ceres), condition number, intervals; the
  /// covariance is diagonal (the file keeps 1-sigmas only). "scale" and "meaning" are derived
  /// from the rest and not read.
  std::vector<CalibrationRun> runs;

  /// The best available result (calibration_method.hpp's rule); nullptr when none is ok.
  const CalibrationRun* best() const& { return bestRun(runs); }
  const CalibrationRun* best() && = delete;  // would point into a temporary
  /// A copy of best(), or InputError(source, ...) when no entry is ok.
  CalibrationRun requireBest() const;
};

/// Parses the JSON: an array of method objects (one object alone counts as an array of one), or
/// the object of several recordings, whose "combined" array is read.
/// Every entry needs a known "method" and a boolean "ok"; an ok entry needs r_L, r_R, b finite
/// and > 0, and joint and ceres entries the three finite lidar keys. Throws InputError naming
/// `source` and the entry's field ("FILE: [2].r_L") otherwise.
CalibrationFile parseCalibrationJson(std::string_view text, const std::string& source);
CalibrationFile readCalibrationJson(const std::filesystem::path& path);

}  // namespace slamprep::algo
