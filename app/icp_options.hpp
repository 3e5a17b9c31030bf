#pragma once
// The scan matcher's flags, the same names and meanings on every command that matches scans
// (match, calibrate): --max-iterations, --max-correspondence-distance, --outlier-sigmas, --trim,
// --line-thickness.

#include <CLI/CLI.hpp>

#include "slamprep/algo/matching/icp.hpp"

namespace slamprep::app {

/// Adds the ICP flags to `cli`, writing into `icp`, whose values are the shown defaults.
void addIcpOptions(CLI::App* cli, algo::IcpParams& icp);

}  // namespace slamprep::app
