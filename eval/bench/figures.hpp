#pragma once
// The suite's plots, rendered off-screen from the summary and the trials' artifacts.

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "eval/bench/suite.hpp"

namespace slamprep::eval {

/// Renders every plot the data supports into out_dir/plots/; returns the file names written.
std::vector<std::string> renderSuitePlots(const Suite& suite, const nlohmann::json& summary,
                                          const std::filesystem::path& out_dir);

}  // namespace slamprep::eval
