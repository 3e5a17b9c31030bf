#pragma once
// One bench trial: simulate, match, calibrate, de-skew, and measure everything against truth.

#include "slamprep/eval/bench/runner.hpp"
#include "slamprep/eval/bench/suite.hpp"

namespace slamprep::eval {

/// The trial function `bench` runs for every trial of `suite` (docs/results.md: result schema).
TrialFunction benchTrial(const Suite& suite);

}  // namespace slamprep::eval
