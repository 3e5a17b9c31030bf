#pragma once
// The robustness section of a faults suite's README (docs/faults.md): per fault condition the
// calibration error of each method, the refusals that name the fault, and the de-skew error.

#include <string>

#include "slamprep/eval/bench/suite_summary.hpp"

namespace slamprep::eval {

/// Markdown section "## Robustness against faults" when the summary's groups sweep
/// `faults.enable`; "" otherwise.
std::string faultRobustnessSection(const SuiteSummary& summary);

}  // namespace slamprep::eval
