#pragma once
// Robustness scoring against injected faults (docs/faults.md): how many events each fault put
// into a trial's data, and whether a method that refused said which fault it saw.

#include <cstddef>
#include <map>
#include <string>

#include "slamprep/core/dataset.hpp"

namespace slamprep::eval {

/// Fault name -> number of injected events, for every fault that was on; empty without any.
/// Faults without discrete events (stamp_jitter, clock_offset, imu_bias_drift, glass) count 1.
std::map<std::string, std::size_t> faultEventCounts(const Dataset& dataset);

/// True when `reason` names a fault that was on in `dataset`: its name ("encoder_spikes"), or
/// the name in words and singular ("encoder spike"), case-insensitively.
bool namesInjectedFault(const std::string& reason, const Dataset& dataset);

}  // namespace slamprep::eval
