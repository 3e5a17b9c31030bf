#pragma once
// The summary's name of a trial record's field: the path flattenMetrics gives its number
// ("calibration/joint/abs_error/b_pct"), which names it in summary.json's "metrics", in trials.csv
// and in a suite's tolerances. Built from the records' key tables, so that a consumer (report,
// figures) names a field by its enum: a renamed or removed field fails to compile there.

#include <string>
#include <string_view>
#include <vector>

#include "slamprep/eval/bench/trial_record.hpp"

namespace slamprep::eval {

/// "sim/<field>".
std::string simMetric(SimField field);
/// "odometry/<geometry>/<field>".
std::string odometryMetric(OdometryGeometry geometry, OdometryField field);
/// "matching/<field>"; the loop closure's under "matching/loop_closure/".
std::string matchingMetric(MatchingField field);
/// "calibration/<method>/<field>".
std::string calibrationMetric(std::string_view method, CalibrationField field);
/// "calibration/<method>/<abs_error|signed_error|sigma>/<parameter key>".
std::string calibrationMetric(std::string_view method, CalibrationError kind,
                              CalibrationParam param);
/// "calibration/<method>/<field>": the method's odometry against the truth.
std::string calibrationMetric(std::string_view method, OdometryField field);
/// "deskew/<method>/<field>".
std::string deskewMetric(std::string_view method, DeskewField field);
/// "deskew/<method>/<figure>".
std::string deskewMetric(std::string_view method, DeskewFigure figure);
/// "deskew/<method>/refused_by_reason/<reason>".
std::string deskewRefusalMetric(std::string_view method, std::string_view reason);

/// "<section>/<method>/": where a method's metrics start.
std::string methodPrefix(TrialSection section, std::string_view method);

/// The method of a metric path under `section` ("joint" of "calibration/joint/ok"); "" when the
/// path is not under it.
std::string methodOfMetric(TrialSection section, std::string_view path);

}  // namespace slamprep::eval
