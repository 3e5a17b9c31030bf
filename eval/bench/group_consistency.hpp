#pragma once
// Is the reported sigma honest? Per group of seeds, each calibration method's signed error
// against the sigma it reported, per parameter, and its mean NEES: summary.json's per-group
// "consistency" (docs/results.md), keyed calibration/<method>/consistency/<param>/<stat> and
// calibration/<method>/consistency/nees_<stat>.

#include <array>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "slamprep/core/enum_names.hpp"
#include "slamprep/eval/bench/calibration_param.hpp"
#include "slamprep/eval/bench/suite_summary.hpp"

namespace slamprep::eval {

/// The statistics of one method and parameter (ErrorConsistency).
enum class ConsistencyStat { kN, kBias, kStd, kRms, kCoverage1Sigma, kCoverage3Sigma };

inline constexpr auto kConsistencyStatKeys = std::to_array<EnumName<ConsistencyStat>>(
    {{ConsistencyStat::kN, "n"},
     {ConsistencyStat::kBias, "bias"},
     {ConsistencyStat::kStd, "std"},
     {ConsistencyStat::kRms, "rms"},
     {ConsistencyStat::kCoverage1Sigma, "coverage_1sigma"},
     {ConsistencyStat::kCoverage3Sigma, "coverage_3sigma"}});

/// The NEES of one method over the group: its mean and how many runs had one.
enum class NeesStat { kMean, kN };

inline constexpr auto kNeesStatKeys =
    std::to_array<EnumName<NeesStat>>({{NeesStat::kMean, "nees_mean"}, {NeesStat::kN, "nees_n"}});

/// "calibration/<method>/consistency/<param>/<stat>".
std::string consistencyMetric(std::string_view method, CalibrationParam param,
                              ConsistencyStat stat);
/// "calibration/<method>/consistency/nees_<stat>".
std::string consistencyMetric(std::string_view method, NeesStat stat);

/// The consistency of every calibration method over `results` (the trial results of one group),
/// from the runs that did not refuse and reported a sigma; empty when none did.
GroupConsistency consistencyOver(const std::vector<const nlohmann::json*>& results);

}  // namespace slamprep::eval
