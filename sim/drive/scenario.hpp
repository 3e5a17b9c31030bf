#pragma once
// Scenarios: what the robot drives, as a piecewise-linear command profile loaded from YAML
// (schema in docs/simulate.md). Every segment starts and ends at rest and respects the scenario's
// acceleration limits, so segments concatenate without jumps.

#include <filesystem>
#include <string>
#include <vector>

#include "slamprep/sim/drive/command_profile.hpp"

namespace slamprep::sim {

/// A scenario file, parsed and expanded into its command profile.
struct Scenario {
  std::string name;
  std::filesystem::path source;
  /// Every file read for it: `source` (when read from disk) and each include, once, in order.
  std::vector<std::filesystem::path> files;
  AccelerationLimits limits;
  CommandProfile profile;
};

/// Loads a scenario file. Throws InputError("file:line: key", ...) on malformed YAML, unknown
/// keys, missing or out-of-range fields and include cycles.
Scenario loadScenario(const std::filesystem::path& file);

/// Parses scenario YAML text; `source` names it in errors and resolves relative includes.
Scenario parseScenario(const std::string& yaml_text, const std::filesystem::path& source);

}  // namespace slamprep::sim
