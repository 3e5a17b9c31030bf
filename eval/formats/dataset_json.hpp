#pragma once
// dataset.json (docs/dataset.md): provenance, geometry and sensor configuration.

#include <string>
#include <string_view>

#include "slamprep/core/dataset.hpp"

namespace slamprep::eval {

/// Pretty-printed dataset.json text. Throws InputError("<file>: <key>") for values that the
/// reader would reject (non-positive radii or ticks, non-finite numbers).
std::string formatDatasetInfo(const DatasetInfo& info, const std::string& file);
/// Throws InputError naming the file, the line (bad JSON) or the key (missing, wrong type,
/// out of range, unsupported format_version).
DatasetInfo parseDatasetInfo(std::string_view text, const std::string& file);

}  // namespace slamprep::eval
