#pragma once
// `slamprep twin --compare REAL TWIN` (docs/twin.md "Comparison"): the statistics a twin must
// reproduce, measured the same way on the recording and on its twin, side by side.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace slamprep::eval {

/// One dataset's statistics (nullopt: could not be measured, e.g. calibration refused).
struct TwinStatistics {
  std::vector<std::pair<std::string, std::optional<double>>> values;  ///< in a fixed order
  std::vector<double> residuals_m;  ///< per accepted scan: RMS point-to-line residual
  bool has_imu = false;  ///< the dataset has gyro samples (and the calibration used them)
};

/// Measures every statistic of docs/twin.md on a dataset folder; without `use_imu` its gyro is
/// left out (a twin always has one: measured as the recording without one is).
TwinStatistics measureTwinStatistics(const std::string& dataset, bool use_imu = true);

struct TwinComparisonRow {
  std::string name;
  std::optional<double> real, twin, ratio;  ///< ratio = twin / real
};

struct TwinComparison {
  std::string real, twin;
  std::vector<TwinComparisonRow> rows;
  std::vector<double> real_residuals_m, twin_residuals_m;
};

TwinComparison compareTwin(const std::string& real, const std::string& twin);
nlohmann::ordered_json comparisonJson(const TwinComparison& c);
std::string comparisonText(const TwinComparison& c);
/// Two panels: twin / real per statistic (log scale, the +-25 % band), and the per-scan
/// residuals of both as box plots.
void plotComparison(const TwinComparison& c, const std::filesystem::path& png);

/// The twin's summary lines from its twin.json.
std::string twinText(const nlohmann::ordered_json& twin_json);

/// How each statistic is measured (docs/twin.md), by name.
const char* statisticDefinition(const std::string& name);

}  // namespace slamprep::eval
