#pragma once
// The suite's plots, rendered off-screen from the summary and the trials' artifacts.

#include <filesystem>
#include <string>
#include <vector>

#include "slamprep/eval/bench/suite.hpp"
#include "slamprep/eval/bench/suite_summary.hpp"

namespace slamprep::eval {

/// The plots a README embeds, in its order.
struct SuitePlots {
  std::vector<std::string> names;  ///< file names under plots/, rendered or kept
  std::vector<std::string> kept;   ///< of those, the ones left as they were (inputs missing)
};

/// Renders every plot the data supports into out_dir/plots/. Without trials/ (a committed
/// results folder: git ignores it) the first trial's figures cannot be rendered, so an existing
/// trajectory.png, odometry_error.png or scan.png is kept untouched and still named.
SuitePlots renderSuitePlots(const Suite& suite, const SuiteSummary& summary,
                            const std::filesystem::path& out_dir);

}  // namespace slamprep::eval
