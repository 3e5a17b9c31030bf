#pragma once
// One de-skew method in a trial ("deskew/<method>" of a trial result): whether it de-skewed every
// scan, the scans it refused (counted by reason, and each one), and its figures against the
// truth. Only the figures measured are written, so that no null enters the summary.

#include <array>
#include <cstddef>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "slamprep/core/enum_names.hpp"
#include "slamprep/eval/pipeline/dataset_deskew.hpp"
#include "slamprep/eval/pipeline/deskew_figures.hpp"

namespace slamprep::eval {

/// The fields of a DeskewRecord besides its figures (kDeskewFigureKeys), by their JSON key.
enum class DeskewField { kOk, kRefusedScans, kRefusedByReason, kRefusals };

inline constexpr auto kDeskewFieldKeys =
    std::to_array<EnumName<DeskewField>>({{DeskewField::kOk, "ok"},
                                          {DeskewField::kRefusedScans, "refused_scans"},
                                          {DeskewField::kRefusedByReason, "refused_by_reason"},
                                          {DeskewField::kRefusals, "refusals"}});

/// One refused scan, as `slamprep deskew --json` lists it (deskewRefusalsJson).
struct DeskewRefusalRecord {
  std::size_t scan = 0;  ///< index in the dataset
  std::string method;    ///< the de-skew method that refused it
  std::string reason;    ///< a countable name (algo::deskewRefusalName)
  std::string detail;    ///< the message

  bool operator==(const DeskewRefusalRecord&) const = default;
};

struct DeskewRecord {
  bool ok = false;                               ///< no scan refused
  int refused_scans = 0;                         ///< refused scans (the next two: when > 0)
  std::map<std::string, int> refused_by_reason;  ///< refused scans by reason name
  std::vector<DeskewRefusalRecord> refusals;     ///< every refused scan (never summarised)
  DeskewFigures figures;                         ///< against the truth, beside the fields above

  bool operator==(const DeskewRecord&) const = default;
};

/// The record of `method`'s de-skew of a dataset.
DeskewRecord deskewRecord(const DatasetDeskew& deskewed, const std::string& method);

void to_json(nlohmann::json& out, const DeskewRecord& r);
void from_json(const nlohmann::json& in, DeskewRecord& r);
void to_json(nlohmann::json& out, const DeskewRefusalRecord& r);
void from_json(const nlohmann::json& in, DeskewRefusalRecord& r);

}  // namespace slamprep::eval
