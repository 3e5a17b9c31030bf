#pragma once
// The results folder's README.md: what a person reads first. Summary tables and the plots.

#include <string>
#include <vector>

#include "slamprep/eval/bench/suite.hpp"
#include "slamprep/eval/bench/suite_summary.hpp"

namespace slamprep::eval {

/// Markdown report of a suite's summary.json; `plots` are file names under plots/ to embed.
/// Deterministic: it depends on the summary alone (no timings, no dates).
std::string renderReport(const Suite& suite, const SuiteSummary& summary,
                         const std::vector<std::string>& plots);

/// The same tables as plain text for the terminal (bench prints it at the end).
std::string renderConsoleSummary(const SuiteSummary& summary);

}  // namespace slamprep::eval
