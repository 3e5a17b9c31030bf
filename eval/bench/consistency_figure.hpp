#pragma once
// consistency.png: is the reported sigma honest? Histograms of error / sigma per calibration
// parameter over a suite's trials, against the unit normal density (docs/plots.md).

#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "slamprep/eval/plot/plot.hpp"

namespace slamprep::eval {

/// One row per trial of a trials.csv (summary.hpp, trialsCsv): metric path -> value; empty cells
/// and the id, world and scenario columns left out. Empty when the file does not exist.
std::vector<std::map<std::string, double>> readTrialRows(const std::filesystem::path& trials_csv);

/// The id column of a trials.csv, one per row of readTrialRows; empty when the file does not
/// exist.
std::vector<std::string> readTrialIds(const std::filesystem::path& trials_csv);

/// One panel per calibration parameter, one step histogram (a density) per method that reports
/// a sigma, and the standard normal density an honest sigma would give. Methods with most runs
/// beyond +-5 sigma are named as off scale instead of drawn. nullopt when no method has a sigma.
/// Reads calibration/<method>/signed_error/<key> and .../sigma/<key> of each row.
std::optional<plot::Figure> consistencyFigure(
    const std::vector<std::map<std::string, double>>& trial_rows);

}  // namespace slamprep::eval
