#pragma once
// `slamprep import --json FILE`: what an import read and decided, as JSON (docs/export.md,
// "Import summary as JSON"). `sensor_agreement` is a placeholder (null) for a later check.

#include <cstddef>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slamprep/core/dataset.hpp"
#include "slamprep/eval/formats/import.hpp"

namespace slamprep::eval {

/// What went into the dataset besides the summary: the dataset without its scans (a spilled
/// import streams them) and how many scans were written.
struct ImportCounts {
  std::size_t scans = 0;
};

nlohmann::ordered_json importSummaryJson(const std::string& input, const std::string& format,
                                         const std::string& out, const ImportSummary& summary,
                                         const Dataset& dataset, const ImportCounts& counts,
                                         const std::vector<std::string>& notes);

}  // namespace slamprep::eval
