#pragma once
// Whether a stream's irregular stamps are right: a sensor that samples irregularly and stamps
// each sample when it took it has stamps a grid would make wrong (docs/deskew.md, "Jittered
// stamps"). Encoder ticks carry their own evidence: they follow the time that really passed.
// A scan's scan_time does not: drivers measure it on the host clock that stamps the scan.

#include <cstddef>
#include <optional>
#include <vector>

#include "slamprep/core/dataset.hpp"

namespace slamprep::algo {

/// How wrong encoder stamps can be, judged by their ticks. Where the wheels turn steadily (the
/// rate over the 3 steps before a step and the 3 after agree within 10 %, and a period turns
/// them by at least 20 ticks) a step's ticks are predicted by the rate over 7 steps around it
/// times the step's duration; a stamp error e_i makes the prediction miss by (e_i - e_{i-1}) / T
/// of a period's ticks, so the robust sigma m of the misses bounds the error:
///   sigma_e <= T m / sqrt(2)                                                          (Eq. 1)
/// (other noise adds to m, never takes off). nullopt: fewer than 30 steady steps.
std::optional<double> tickStampErrorBound(const std::vector<EncoderSample>& encoders);

}  // namespace slamprep::algo
