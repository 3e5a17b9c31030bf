#pragma once
// A method's de-skew of a dataset as JSON: the figures against the truth and the refused scans,
// written once for `slamprep deskew --json` (docs/deskew.md) and a bench trial's "deskew"
// (docs/results.md).

#include <nlohmann/json.hpp>
#include <string_view>

#include "slamprep/eval/pipeline/dataset_deskew.hpp"
#include "slamprep/eval/pipeline/deskew_figures.hpp"

namespace slamprep::eval {

/// How a figure the dataset cannot give (no truth, scans not repacked) is written.
enum class AbsentFigure {
  kNull,     ///< as null, so that every method's object has the same keys (deskew --json)
  kOmitted,  ///< left out, so that only measured numbers enter a suite's summary (bench)
};

/// The error figures under kDeskewFigureKeys, in that order (with kNull, 0 beams without truth).
nlohmann::ordered_json deskewFiguresJson(const DeskewFigures& figures, AbsentFigure absent);
nlohmann::ordered_json deskewFiguresJson(const DatasetDeskew& deskewed, AbsentFigure absent);

/// The figures of an object written by deskewFiguresJson with `absent`; other keys are not read.
/// A null is an absent figure with kNull, a non-finite one (NaN) with kOmitted.
DeskewFigures deskewFiguresFromJson(const nlohmann::json& in, AbsentFigure absent);

/// Every refused scan in order, [{"scan", "method", "reason", "detail"}]; [] when none.
nlohmann::ordered_json deskewRefusalsJson(const DatasetDeskew& deskewed, std::string_view method);

}  // namespace slamprep::eval
