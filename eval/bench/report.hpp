#pragma once
// The results folder's README.md: what a person reads first. Summary tables and the plots.

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slamprep/eval/bench/suite.hpp"

namespace slamprep::eval {

/// Markdown report of a suite's summary.json; `plots` are file names under plots/ to embed.
/// Deterministic: it depends on the summary alone (no timings, no dates).
std::string renderReport(const Suite& suite, const nlohmann::json& summary,
                         const std::vector<std::string>& plots);

/// The same tables as plain text for the terminal (bench prints it at the end).
std::string renderConsoleSummary(const nlohmann::json& summary);

}  // namespace slamprep::eval
